// Progress on stderr: a redrawn bar with percentage, elapsed time and ETA on a terminal,
// plain lines every ten percent otherwise (logs stay readable). Under a time limit the render
// ends at the limit or at its samples, whichever comes first: the progress is the larger share.
#pragma once
#include <chrono>
#include <cstdint>

namespace spt {

class ProgressBar {
public:
    /// time_limit: seconds (0: none).
    explicit ProgressBar(bool enabled, double time_limit = 0);
    void update(std::uint64_t done, std::uint64_t total);
    /// Ends the bar's line (call once after the last update).
    void finish();

private:
    bool m_enabled;
    double m_time_limit;
    bool m_terminal;
    int m_last_decile = -1;
    bool m_drawn = false;
    std::chrono::steady_clock::time_point m_start;
};

}  // namespace spt
