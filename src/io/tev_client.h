// A client of the tev image viewer's display-server protocol: the render appears in tev while
// it runs. TCP over POSIX sockets; tev listens on 127.0.0.1:14158 by default.
//
// Packet layout (tev, https://github.com/Tom94/tev: include/tev/Ipc.h, IpcPacket::OStream and
// EType; src/Ipc.cpp, IpcPacket::setCreateImage / setUpdateImage and SocketConnection::service;
// src/python/ipc.py; read at commit 023a0f2, 2025). Every integer is little-endian, a float is
// IEEE-754 binary32 little-endian, a bool one byte (0 or 1), a string its UTF-8 bytes and a 0.
//
//   every packet   u32 length (of the whole packet, these 4 bytes included), u8 type, fields
//   CreateImage    type 4: bool grab_focus, string name, i32 width, i32 height,
//                  i32 channel count n, n strings (channel names)
//   UpdateImage v3 type 6: bool grab_focus, string name, i32 n, n strings (channel names),
//                  i32 x, i32 y, i32 width, i32 height (the region updated),
//                  n i64 offsets, n i64 strides (in floats), then the floats: channel c of
//                  region pixel p (row-major) is float number offset[c] + p * stride[c], and
//                  there are max over c of (offset[c] + (pixels - 1) * stride[c] + 1) floats
//
// This client sends channels R, G, B interleaved (offsets 0, 1, 2; strides 3), the image in
// bands of whole rows of at most kTevMaxFloatsPerPacket floats (tev's receive buffer starts at
// 1 MiB and grows, and the length field is 32-bit: big images must be split anyway).
#pragma once
#include <optional>
#include <string>

#include "io/image.h"

namespace spt {

constexpr int kTevDefaultPort = 14158;
constexpr int kTevMaxFloatsPerPacket = 1 << 20;  // 4 MiB of pixel data

struct DisplayServerAddress {
    std::string host;
    int port = kTevDefaultPort;
    /// "host:port" ("[host]:port" for an IPv6 address), as the user would write it.
    std::string describe() const;
};

/// Parses HOST or HOST:PORT (PORT 1 to 65535, default kTevDefaultPort); an IPv6 address in
/// brackets: [::1] or [::1]:14158. nullopt when the host is empty or the port is malformed.
std::optional<DisplayServerAddress> parse_display_server(const std::string& text);

/// The CreateImage packet of an image with channels R, G, B (grab_focus set: tev shows it).
std::string tev_create_image_packet(const std::string& name, int width, int height);

/// The UpdateImage (v3) packet of rows [y0, y0 + rows) of `image` (channels R, G, B).
std::string tev_update_image_packet(const std::string& name, const Image& image, int y0, int rows);

/// Rows per UpdateImage packet for an image this wide (at least 1).
int tev_rows_per_packet(int width);

/// A connection to a tev instance. Sends never raise SIGPIPE; a send that cannot finish in
/// 10 s fails (a stalled viewer must not stall the render).
class TevClient {
public:
    /// Connects (3 s timeout). Throws std::runtime_error "cannot connect to display server
    /// ADDRESS: reason".
    explicit TevClient(const DisplayServerAddress& address);
    ~TevClient();
    TevClient(const TevClient&) = delete;
    TevClient& operator=(const TevClient&) = delete;

    /// Creates (or replaces) the image `name` in tev, black, channels R, G, B.
    /// Like update_image, throws std::runtime_error "display server ADDRESS: reason" when
    /// the send fails.
    void create_image(const std::string& name, int width, int height);
    /// Sends every pixel of `image` (linear RGB) to the image `name`, in bands of rows.
    void update_image(const std::string& name, const Image& image);

private:
    void send_all(const std::string& bytes);
    int m_socket = -1;
    std::string m_address;
};

}  // namespace spt
