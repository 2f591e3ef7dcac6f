// PLY reader: ASCII and binary little-endian meshes generated here, fan triangulation, and
// clean errors for broken files (sizes checked before allocation).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "io/located_error.h"
#include "io/ply_reader.h"

namespace spt {
namespace {

const char* kAsciiQuad =
    "ply\nformat ascii 1.0\ncomment a unit square\nelement vertex 4\nproperty float x\n"
    "property float y\nproperty float z\nproperty float nx\nelement face 1\n"
    "property list uchar int vertex_indices\nend_header\n"
    "0 0 0 9\n1 0 0 9\n1 1 0 9\n0 1 0 9\n4 0 1 2 3\n";

std::string error_of(const std::string& bytes) {
    try {
        parse_ply(bytes, "m.ply");
    } catch (const LocatedError& e) {
        return e.what();
    }
    return "(no error)";
}

template <typename T>
void put(std::string& out, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));  // the test host is little-endian (x86-64, aarch64)
    out.append(b, sizeof(T));
}

std::string binary_tetrahedron(bool use_double, std::uint32_t declared_faces = 4) {
    std::string s = "ply\r\nformat binary_little_endian 1.0\r\nelement vertex 4\r\n";
    const char* t = use_double ? "double" : "float";
    s += std::string("property ") + t + " x\r\nproperty " + t + " y\r\nproperty " + t + " z\r\n";
    s += "element face " + std::to_string(declared_faces) + "\r\nproperty list uchar uint vertex_indices\r\nend_header\r\n";
    const double p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const auto& v : p)
        for (double c : v) use_double ? put(s, c) : put(s, static_cast<float>(c));
    const std::uint32_t f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (const auto& face : f) {
        put<std::uint8_t>(s, 3);
        for (std::uint32_t i : face) put(s, i);
    }
    return s;
}

TEST(Ply, AsciiPolygonIsFanTriangulated) {
    const PlyMesh m = parse_ply(kAsciiQuad, "m.ply");
    ASSERT_EQ(m.positions.size(), 4u);
    EXPECT_EQ(m.positions[2], Vec3(1, 1, 0));
    ASSERT_EQ(m.triangles.size(), 2u);
    EXPECT_EQ(m.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
    EXPECT_EQ(m.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
}

TEST(Ply, BinaryLittleEndianFloatAndDouble) {
    for (bool dbl : {false, true}) {
        const PlyMesh m = parse_ply(binary_tetrahedron(dbl), "m.ply");
        ASSERT_EQ(m.positions.size(), 4u);
        ASSERT_EQ(m.triangles.size(), 4u);
        EXPECT_EQ(m.positions[3], Vec3(0, 0, 1));
        EXPECT_EQ(m.triangles[3], (std::array<std::uint32_t, 3>{1, 2, 3}));
    }
}

TEST(Ply, BrokenFilesGiveLocatedErrors) {
    EXPECT_NE(error_of("").find("m.ply:1:1: not a PLY file"), std::string::npos);
    std::string truncated = binary_tetrahedron(false);
    truncated.resize(truncated.size() - 3);
    EXPECT_NE(error_of(truncated).find("needs more data than the rest of the file"), std::string::npos);
    EXPECT_NE(error_of(binary_tetrahedron(false, 4000000000u)).find("declares 4000000000 items"), std::string::npos);
    std::string bad_index = kAsciiQuad;
    bad_index.replace(bad_index.find("4 0 1 2 3"), 9, "4 0 1 2 7");
    EXPECT_NE(error_of(bad_index).find("m.ply:16:9: face 0 refers to vertex 7"), std::string::npos);
    std::string nan = kAsciiQuad;
    nan.replace(nan.find("1 1 0 9"), 7, "1 nan 0 9");
    EXPECT_NE(error_of(nan).find("m.ply:14:"), std::string::npos);
    std::string big_endian = kAsciiQuad;
    big_endian.replace(big_endian.find("ascii"), 5, "binary_big_endian");
    EXPECT_NE(error_of(big_endian).find("not supported"), std::string::npos);
    std::string two = kAsciiQuad;
    two.replace(two.find("4 0 1 2 3"), 9, "2 0 1");
    EXPECT_NE(error_of(two).find("expected at least 3"), std::string::npos);
    EXPECT_NE(error_of(std::string(kAsciiQuad) + "junk").find("after the last element"), std::string::npos);
}

}  // namespace
}  // namespace spt
