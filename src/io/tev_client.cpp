// tev's display-server protocol: packet encoding (layout in the header) and the TCP client.
#include "io/tev_client.h"

#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <stdexcept>

#include "io/image_encoders.h"

namespace spt {

namespace {

constexpr char kCreateImage = 4;
constexpr char kUpdateImageV3 = 6;
constexpr const char* kChannels[3] = {"R", "G", "B"};
constexpr int kConnectTimeoutMs = 3000;
constexpr int kSendTimeoutSeconds = 10;

void append_string(std::string& out, const std::string& s) {
    out += s;
    out.push_back('\0');
}

/// Starts a packet: room for the length, then the type.
std::string begin_packet(char type) {
    std::string p(4, '\0');
    p.push_back(type);
    return p;
}

/// Writes the length field, once every field is in.
std::string finish_packet(std::string p) {
    std::string length;
    append_le32(length, static_cast<std::uint32_t>(p.size()));
    p.replace(0, 4, length);
    return p;
}

/// Connects a socket to one resolved address, waiting at most kConnectTimeoutMs; returns the
/// socket, or -1 with errno set.
int connect_with_timeout(const addrinfo& ai) {
    const int fd = ::socket(ai.ai_family, ai.ai_socktype, ai.ai_protocol);
    if (fd < 0) return -1;
    // Non-blocking connect + poll: a host that drops packets would otherwise block for minutes.
    const int flags = ::fcntl(fd, F_GETFL, 0);
    ::fcntl(fd, F_SETFL, flags | O_NONBLOCK);
    int err = 0;
    if (::connect(fd, ai.ai_addr, ai.ai_addrlen) != 0) {
        err = errno;
        if (err == EINPROGRESS) {
            pollfd pfd{fd, POLLOUT, 0};
            const int ready = ::poll(&pfd, 1, kConnectTimeoutMs);
            socklen_t len = sizeof err;
            if (ready == 0) err = ETIMEDOUT;
            else if (ready < 0) err = errno;
            else if (::getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len) != 0) err = errno;
        }
    }
    if (err != 0) {
        ::close(fd);
        errno = err;
        return -1;
    }
    ::fcntl(fd, F_SETFL, flags);
    const timeval timeout{kSendTimeoutSeconds, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
    return fd;
}

}  // namespace

std::string DisplayServerAddress::describe() const {
    const bool ipv6 = host.find(':') != std::string::npos;
    return (ipv6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
}

std::optional<DisplayServerAddress> parse_display_server(const std::string& text) {
    DisplayServerAddress address;
    std::string port;
    if (!text.empty() && text[0] == '[') {  // [IPv6] or [IPv6]:PORT
        const std::size_t close = text.find(']');
        if (close == std::string::npos) return std::nullopt;
        address.host = text.substr(1, close - 1);
        if (close + 1 < text.size()) {
            if (text[close + 1] != ':') return std::nullopt;
            port = text.substr(close + 2);
            if (port.empty()) return std::nullopt;
        }
    } else if (const std::size_t colon = text.find(':'); colon != std::string::npos) {
        address.host = text.substr(0, colon);
        port = text.substr(colon + 1);
        if (port.empty()) return std::nullopt;
    } else {
        address.host = text;
    }
    if (address.host.empty()) return std::nullopt;
    if (!port.empty()) {
        const char* end = port.data() + port.size();
        const auto [ptr, ec] = std::from_chars(port.data(), end, address.port);
        if (ec != std::errc() || ptr != end || address.port < 1 || address.port > 65535) return std::nullopt;
    }
    return address;
}

std::string tev_create_image_packet(const std::string& name, int width, int height) {
    std::string p = begin_packet(kCreateImage);
    p.push_back(1);  // grab focus: show the render as it starts
    append_string(p, name);
    append_le32(p, static_cast<std::uint32_t>(width));
    append_le32(p, static_cast<std::uint32_t>(height));
    append_le32(p, 3);
    for (const char* channel : kChannels) append_string(p, channel);
    return finish_packet(std::move(p));
}

std::string tev_update_image_packet(const std::string& name, const Image& image, int y0, int rows) {
    std::string p = begin_packet(kUpdateImageV3);
    p.push_back(0);  // no grab focus: the user may be looking at another image
    append_string(p, name);
    append_le32(p, 3);
    for (const char* channel : kChannels) append_string(p, channel);
    append_le32(p, 0);
    append_le32(p, static_cast<std::uint32_t>(y0));
    append_le32(p, static_cast<std::uint32_t>(image.width));
    append_le32(p, static_cast<std::uint32_t>(rows));
    for (int c = 0; c < 3; ++c) append_le64(p, static_cast<std::uint64_t>(c));  // offsets
    for (int c = 0; c < 3; ++c) append_le64(p, 3);                              // strides
    const std::size_t floats = static_cast<std::size_t>(image.width) * rows * 3;
    p.reserve(p.size() + 4 * floats);
    const float* data = image.pixel(0, y0);
    for (std::size_t i = 0; i < floats; ++i) append_le_float(p, data[i]);
    return finish_packet(std::move(p));
}

int tev_rows_per_packet(int width) {
    return std::max(1, kTevMaxFloatsPerPacket / (3 * std::max(1, width)));
}

TevClient::TevClient(const DisplayServerAddress& address) : m_address(address.describe()) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    const std::string port = std::to_string(address.port);
    if (const int err = ::getaddrinfo(address.host.c_str(), port.c_str(), &hints, &found); err != 0)
        throw std::runtime_error("cannot connect to display server " + m_address + ": " +
                                 ::gai_strerror(err));
    int last_error = ECONNREFUSED;
    for (const addrinfo* ai = found; ai && m_socket < 0; ai = ai->ai_next) {
        m_socket = connect_with_timeout(*ai);
        if (m_socket < 0) last_error = errno;
    }
    ::freeaddrinfo(found);
    if (m_socket < 0)
        throw std::runtime_error("cannot connect to display server " + m_address + ": " +
                                 std::strerror(last_error));
}

TevClient::~TevClient() {
    if (m_socket >= 0) ::close(m_socket);
}

void TevClient::create_image(const std::string& name, int width, int height) {
    send_all(tev_create_image_packet(name, width, height));
}

void TevClient::update_image(const std::string& name, const Image& image) {
    const int band = tev_rows_per_packet(image.width);
    for (int y0 = 0; y0 < image.height; y0 += band)
        send_all(tev_update_image_packet(name, image, y0, std::min(band, image.height - y0)));
}

void TevClient::send_all(const std::string& bytes) {
    std::size_t sent = 0;
    while (sent < bytes.size()) {
        // MSG_NOSIGNAL: a viewer that went away is an error to report, not a SIGPIPE to die of.
        const ssize_t n = ::send(m_socket, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;  // e.g. SIGINT arriving: finish the packet
        if (n < 0) {
            const int err = errno == EAGAIN || errno == EWOULDBLOCK ? ETIMEDOUT : errno;
            throw std::runtime_error("display server " + m_address + ": " + std::strerror(err));
        }
        sent += static_cast<std::size_t>(n);
    }
}

}  // namespace spt
