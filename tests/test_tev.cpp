// The tev display-server protocol, checked against a protocol-level fake server: the test
// listens on 127.0.0.1, runs the program with --display-server, parses every packet byte by
// byte (layout in src/io/tev_client.h, from tev's src/Ipc.cpp) and compares the image the
// packets build with the PFM the same run writes.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "io/tev_client.h"
#include "program_process.h"

namespace {

namespace fs = std::filesystem;
using test::read_file;

TEST(DisplayServerAddress, ParsesHostAndOptionalPort) {
    struct Case {
        const char* text;
        const char* host;
        int port;
    };
    const Case good[] = {{"localhost", "localhost", 14158}, {"127.0.0.1:1", "127.0.0.1", 1},
                         {"viewer.lan:65535", "viewer.lan", 65535}, {"[::1]", "::1", 14158},
                         {"[::1]:9000", "::1", 9000}};
    for (const Case& c : good) {
        const auto a = spt::parse_display_server(c.text);
        ASSERT_TRUE(a) << c.text;
        EXPECT_EQ(a->host, c.host) << c.text;
        EXPECT_EQ(a->port, c.port) << c.text;
        const auto again = spt::parse_display_server(a->describe());  // describe() reads back
        ASSERT_TRUE(again) << a->describe();
        EXPECT_EQ(again->host, a->host);
        EXPECT_EQ(again->port, a->port);
    }
    for (const char* bad : {"", ":14158", "host:", "host:0", "host:65536", "host:x", "host:1:2", "[::1",
                            "[::1]9000", "[]:5", "host:-1"})
        EXPECT_FALSE(spt::parse_display_server(bad)) << bad;
}

/// A listening socket on 127.0.0.1 at a port the system chose.
struct FakeServer {
    int fd = -1;
    int port = 0;
    FakeServer() {
        fd = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in addr{};
        addr.sin_family = AF_INET;
        addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        addr.sin_port = 0;
        socklen_t len = sizeof addr;
        if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || ::listen(fd, 1) != 0 ||
            ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0)
            return;
        port = ntohs(addr.sin_port);
    }
    ~FakeServer() { ::close(fd); }
    /// Accepts one client and reads everything it sends until it closes the connection.
    std::string receive_all(int timeout_ms = 120000) const {
        pollfd pfd{fd, POLLIN, 0};
        if (::poll(&pfd, 1, timeout_ms) != 1) return {};
        const int client = ::accept(fd, nullptr, nullptr);
        std::string bytes;
        char buffer[1 << 16];
        for (ssize_t n; (n = ::recv(client, buffer, sizeof buffer, 0)) > 0;)
            bytes.append(buffer, std::size_t(n));
        ::close(client);
        return bytes;
    }
};

/// Reads the protocol's little-endian fields; any read past the end sets `overrun`.
class PacketReader {
public:
    PacketReader(const std::string& bytes, std::size_t begin, std::size_t end)
        : m_bytes(bytes), m_pos(begin), m_end(end) {}
    std::uint64_t unsigned_le(int size) {
        if (m_pos + std::size_t(size) > m_end) return overrun = true, 0;
        std::uint64_t v = 0;
        for (int i = 0; i < size; ++i) v |= std::uint64_t(std::uint8_t(m_bytes[m_pos + i])) << (8 * i);
        m_pos += std::size_t(size);
        return v;
    }
    std::int32_t i32() { return static_cast<std::int32_t>(unsigned_le(4)); }
    std::int64_t i64() { return static_cast<std::int64_t>(unsigned_le(8)); }
    float f32() { return std::bit_cast<float>(static_cast<std::uint32_t>(unsigned_le(4))); }
    int byte() { return static_cast<int>(unsigned_le(1)); }
    std::string string() {
        const std::size_t zero = m_bytes.find('\0', m_pos);
        if (zero == std::string::npos || zero >= m_end) return overrun = true, std::string();
        std::string s = m_bytes.substr(m_pos, zero - m_pos);
        m_pos = zero + 1;
        return s;
    }
    bool at_end() const { return m_pos == m_end; }
    bool overrun = false;

private:
    const std::string& m_bytes;
    std::size_t m_pos, m_end;
};

/// What the packets did: the image they build (R, G, B floats, row-major, top row first).
struct ViewerState {
    std::string name;
    int width = 0, height = 0;
    std::vector<float> rgb;
    int creates = 0;
    int whole_updates = 0;  ///< UpdateImage packets covering row 0 (one per image sent)
    std::vector<int> band_rows;  ///< rows of each UpdateImage packet of the last image sent
};

/// Parses the stream packet by packet, checking every field against the protocol.
ViewerState replay(const std::string& stream) {
    ViewerState v;
    std::size_t at = 0;
    while (at < stream.size()) {
        PacketReader header(stream, at, stream.size());
        const std::uint32_t length = static_cast<std::uint32_t>(header.unsigned_le(4));
        EXPECT_GE(length, 5u) << "packet at byte " << at;
        EXPECT_LE(std::size_t(length), stream.size() - at) << "packet at byte " << at << " is cut short";
        if (length < 5 || std::size_t(length) > stream.size() - at) break;
        PacketReader p(stream, at + 4, at + length);
        const int type = p.byte();
        const int grab_focus = p.byte();
        EXPECT_TRUE(grab_focus == 0 || grab_focus == 1);
        const std::string name = p.string();
        if (type == 4) {  // CreateImage
            ++v.creates;
            EXPECT_EQ(grab_focus, 1) << "the render is shown as it starts";
            v.name = name;
            v.width = p.i32();
            v.height = p.i32();
            EXPECT_EQ(p.i32(), 3);
            for (const char* channel : {"R", "G", "B"}) EXPECT_EQ(p.string(), channel);
            v.rgb.assign(std::size_t(v.width) * v.height * 3, -1.f);  // -1: never sent
        } else if (type == 6) {  // UpdateImage v3
            EXPECT_EQ(v.creates, 1) << "UpdateImage before CreateImage";
            EXPECT_EQ(name, v.name);
            const int channels = p.i32();
            EXPECT_EQ(channels, 3);
            if (channels != 3) break;
            for (const char* channel : {"R", "G", "B"}) EXPECT_EQ(p.string(), channel);
            const int x = p.i32(), y = p.i32(), w = p.i32(), h = p.i32();
            EXPECT_TRUE(x >= 0 && y >= 0 && w > 0 && h > 0 && x + w <= v.width && y + h <= v.height)
                << x << " " << y << " " << w << " " << h;
            if (!(x >= 0 && y >= 0 && w > 0 && h > 0 && x + w <= v.width && y + h <= v.height)) break;
            std::int64_t offset[3], stride[3];
            for (std::int64_t& o : offset) o = p.i64();
            for (std::int64_t& s : stride) s = p.i64();
            const std::int64_t pixels = std::int64_t(w) * h;
            std::int64_t floats = 0;
            for (int c = 0; c < 3; ++c) floats = std::max(floats, offset[c] + (pixels - 1) * stride[c] + 1);
            std::vector<float> data(static_cast<std::size_t>(floats));
            for (float& f : data) f = p.f32();
            if (y == 0) {
                ++v.whole_updates;
                v.band_rows.clear();
            }
            v.band_rows.push_back(h);
            for (std::int64_t i = 0; i < pixels; ++i)
                for (int c = 0; c < 3; ++c) {
                    const std::size_t px = std::size_t(y + i / w) * v.width + std::size_t(x + i % w);
                    v.rgb[3 * px + c] = data[std::size_t(offset[c] + i * stride[c])];
                }
        } else {
            ADD_FAILURE() << "unexpected packet type " << type;
        }
        EXPECT_FALSE(p.overrun) << "packet of type " << type << " is shorter than its fields";
        EXPECT_TRUE(p.at_end()) << "packet of type " << type << " has bytes after its fields";
        at += length;
    }
    return v;
}

/// The floats of a PFM written by the program, top row first (PFM stores bottom row first).
std::vector<float> pfm_pixels(const std::string& bytes, int width, int height) {
    const std::string header = "PF\n" + std::to_string(width) + " " + std::to_string(height) + "\n-1.0\n";
    std::vector<float> rgb(std::size_t(width) * height * 3);
    if (bytes.rfind(header, 0) != 0 || bytes.size() != header.size() + rgb.size() * 4) return {};
    PacketReader r(bytes, header.size(), bytes.size());
    for (int y = height - 1; y >= 0; --y)
        for (std::size_t i = 0; i < std::size_t(width) * 3; ++i)
            rgb[std::size_t(y) * width * 3 + i] = r.f32();
    return rgb;
}

class DisplayServer : public ::testing::Test {
protected:
    void SetUp() override {
        dir = test::fresh_test_dir("tev");
    }
    void TearDown() override { fs::remove_all(dir); }

    /// Runs a render of width x height shown on the fake server; returns what the server saw.
    ViewerState render_to_fake_server(int width, int height, const std::vector<std::string>& more) {
        FakeServer server;
        EXPECT_GT(server.port, 0);
        std::vector<std::string> args = {
            "--width", std::to_string(width), "--height", std::to_string(height), "--threads", "2",
            "--seed", "11", "--color-space", "rec2020",
            "--display-server", "127.0.0.1:" + std::to_string(server.port),
            "-o", (dir / "render.pfm").string(), "-o", (dir / "render.png").string()};
        args.insert(args.end(), more.begin(), more.end());
        const pid_t pid = test::spawn(args, dir / "log");
        const std::string stream = server.receive_all();
        EXPECT_EQ(test::wait_exit(pid), 0) << read_file(dir / "log");
        return replay(stream);
    }
    fs::path dir;
};

/// One CreateImage named after the output, then the whole image after passes (each of the 4,
/// unless the image of the one before is still being sent) and once more at the end; the
/// last one equals, float for float, the PFM of the same run (linear, output colour space).
TEST_F(DisplayServer, FakeServerSeesThePassesAndTheFinalImageEqualsThePfm) {
    const int width = 200, height = 150;  // passes of 60000 paths: the viewer keeps up
    const ViewerState v = render_to_fake_server(width, height, {"--spp", "8", "--pass-spp", "2"});
    EXPECT_EQ(v.creates, 1);
    EXPECT_EQ(v.name, "render");
    EXPECT_EQ(v.width, width);
    EXPECT_EQ(v.height, height);
    EXPECT_GE(v.whole_updates, 1 + 1) << "at least one during the render, and the last";
    EXPECT_LE(v.whole_updates, 4 + 1);
    const std::vector<float> pfm = pfm_pixels(read_file(dir / "render.pfm"), width, height);
    ASSERT_FALSE(pfm.empty()) << "render.pfm is not a PFM of the render's size";
    EXPECT_EQ(std::memcmp(v.rgb.data(), pfm.data(), pfm.size() * sizeof(float)), 0);
    EXPECT_NE(read_file(dir / "log").find("preview: image 'render' on the display server 127.0.0.1:"),
              std::string::npos)
        << read_file(dir / "log");
}

/// An image too big for one packet goes in bands of whole rows that tile it.
TEST_F(DisplayServer, BigImagesAreSentInBandsOfRows) {
    const int width = 700, height = 520;  // 1.09 million floats: two packets
    const ViewerState v = render_to_fake_server(width, height, {"--spp", "1"});
    const int rows = spt::tev_rows_per_packet(width);
    EXPECT_LE(std::int64_t(rows) * width * 3, spt::kTevMaxFloatsPerPacket);
    EXPECT_EQ(v.band_rows, (std::vector<int>{rows, height - rows}));
    const std::vector<float> pfm = pfm_pixels(read_file(dir / "render.pfm"), width, height);
    ASSERT_FALSE(pfm.empty());
    EXPECT_EQ(std::memcmp(v.rgb.data(), pfm.data(), pfm.size() * sizeof(float)), 0);
}

/// No viewer listening: one warning line naming the address, and the render goes on.
TEST_F(DisplayServer, UnreachableServerIsAWarningAndTheRenderGoesOn) {
    int port = 0;
    {
        FakeServer closed;  // a port that was free a moment ago and has no listener now
        port = closed.port;
    }
    const std::string address = "127.0.0.1:" + std::to_string(port);
    EXPECT_EQ(test::run({"--width", "8", "--height", "8", "--spp", "2", "--quiet", "--display-server",
                         address, "-o", (dir / "out.pfm").string()},
                        dir / "log"),
              0);
    const std::string log = read_file(dir / "log");
    EXPECT_NE(log.find("pathtracer: warning: cannot connect to display server " + address), std::string::npos)
        << log;
    EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << log;
    EXPECT_TRUE(fs::exists(dir / "out.pfm"));
}

/// A viewer that goes away during the render (tev closed): no SIGPIPE, a one-line warning,
/// and the render finishes and writes its image.
TEST_F(DisplayServer, ViewerClosingDuringTheRenderIsAWarning) {
    FakeServer server;
    ASSERT_GT(server.port, 0);
    const pid_t pid = test::spawn({"--width", "200", "--height", "150", "--spp", "8", "--pass-spp", "1",
                                   "--quiet", "--display-server", "127.0.0.1:" + std::to_string(server.port),
                                   "-o", (dir / "out.pfm").string()},
                                  dir / "log");
    pollfd pfd{server.fd, POLLIN, 0};
    ASSERT_EQ(::poll(&pfd, 1, 60000), 1);
    ::close(::accept(server.fd, nullptr, nullptr));  // the viewer is closed at once
    EXPECT_EQ(test::wait_exit(pid), 0) << read_file(dir / "log");
    EXPECT_TRUE(fs::exists(dir / "out.pfm"));
    const std::string log = read_file(dir / "log");
    EXPECT_NE(log.find("pathtracer: warning: display server 127.0.0.1:"), std::string::npos) << log;
    EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << log;
}

}  // namespace
