#include "cli/progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <string>

namespace spt {

namespace {

std::string format_seconds(double s) {
    char buf[32];
    const int total = static_cast<int>(s + 0.5);
    if (total >= 3600)
        std::snprintf(buf, sizeof buf, "%d:%02d:%02d", total / 3600, total / 60 % 60, total % 60);
    else
        std::snprintf(buf, sizeof buf, "%d:%02d", total / 60, total % 60);
    return buf;
}

}  // namespace

ProgressBar::ProgressBar(bool enabled, double time_limit)
    : m_enabled(enabled), m_time_limit(time_limit), m_terminal(isatty(STDERR_FILENO)), m_start(std::chrono::steady_clock::now()) {}

void ProgressBar::update(std::uint64_t done, std::uint64_t total) {
    if (!m_enabled || total == 0) return;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    double fraction = static_cast<double>(done) / static_cast<double>(total);
    if (m_time_limit > 0) fraction = std::min(1.0, std::max(fraction, elapsed / m_time_limit));
    const std::string eta = fraction > 0 ? format_seconds(elapsed * (1 - fraction) / fraction) : "?";
    if (m_terminal) {
        constexpr int kWidth = 40;
        const int filled = static_cast<int>(fraction * kWidth);
        std::string bar(filled, '#');
        bar.resize(kWidth, '.');
        std::fprintf(stderr, "\r[%s] %5.1f%%  elapsed %s  ETA %s ", bar.c_str(), 100 * fraction,
                     format_seconds(elapsed).c_str(), eta.c_str());
        std::fflush(stderr);
        m_drawn = true;
        return;
    }
    const int decile = static_cast<int>(fraction * 10);
    if (decile == m_last_decile) return;
    m_last_decile = decile;
    std::fprintf(stderr, "progress %3d%%  elapsed %s  ETA %s\n", decile * 10,
                 format_seconds(elapsed).c_str(), eta.c_str());
}

void ProgressBar::finish() {
    if (m_enabled && m_terminal && m_drawn) std::fprintf(stderr, "\n");
}

}  // namespace spt
