// Live previews: while the render runs, its unfinished image is rewritten under the outputs'
// partial names (so any viewer that reloads them shows the progress) and sent to a tev viewer.
// The rendering thread copies the film at a pass boundary, when no worker writes it (so the
// render is unchanged), and a writer thread encodes and sends the copy while the render goes
// on: a preview costs the workers a copy of the film, not an image encoding.
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "io/tev_client.h"
#include "render/film.h"
#include "spectral/color_space.h"

namespace spt {

struct PreviewSettings {
    std::vector<std::string> outputs;  ///< final names; preview files go to their partial names
    std::optional<double> interval;    ///< seconds between previews (nullopt: no preview files)
    std::optional<DisplayServerAddress> display_server;  ///< a tev viewer, or none
    ColorSpace space;                  ///< linear RGB sent to the viewer (the outputs' space)
    bool quiet = false;                ///< no "preview:" lines (warnings are always printed)
};

/// Pass length the renderer should aim at (RenderSettings::pass_seconds) so that previews come
/// on time: half the interval (a preview is then at most 1.5 intervals after the last), one
/// second for a viewer without an interval; 0 (automatic passes) when nothing is previewed or
/// the interval is 0 (a preview after every pass, whatever its length).
double preview_pass_seconds(const PreviewSettings& settings);

class LivePreview {
public:
    /// Writes the film's image to these paths, atomically, all or nothing (throws on failure).
    using WriteImages =
        std::function<void(const std::vector<std::string>& paths, const Film& film)>;

    /// Says what will be previewed (stderr, unless quiet), connects to the display server and
    /// creates the image there. A viewer that cannot be reached is a one-line warning: the
    /// render goes on without it.
    LivePreview(PreviewSettings settings, WriteImages write, int width, int height);
    /// Waits for a preview being written (see render_ended).
    ~LivePreview();

    /// At a pass boundary (the film is whole): a preview once `interval` seconds have passed
    /// since the last one started (or the render did), or after every pass for a viewer
    /// without interval: the preview files and the viewer. Skipped while the last preview is
    /// still being written (tried again at the next pass). A failure is a one-line warning
    /// and ends that kind of preview; the render goes on.
    void pass_completed(const Film& film);

    /// The render is over (finished or interrupted): waits for a preview being written (so
    /// no preview lands after the final images) and sends the viewer the last film.
    void render_ended(const Film& film);

    /// Once the finished images are written: removes the partial files this run wrote
    /// (an unfinished image from an earlier run is not this run's to remove).
    void remove_preview_files();

private:
    void writer_loop();
    void stop_writer();
    void show(const Film& film);

    PreviewSettings m_settings;
    WriteImages m_write;
    int m_width, m_height;
    std::vector<std::string> m_partial_names;
    std::string m_viewer_image;  ///< the name of the image in the viewer: the output's stem
    std::unique_ptr<TevClient> m_viewer;
    std::chrono::steady_clock::time_point m_last_preview;

    // Writer thread: one preview at a time, from a copy of the film state.
    std::atomic<bool> m_files_on{false}, m_viewer_on{false};  ///< off after a failure
    bool m_wrote_files = false;  ///< read once the writer has stopped
    std::mutex m_mutex;
    std::condition_variable m_wake;
    std::optional<std::string> m_job;  ///< film state waiting for the writer
    bool m_busy = false, m_stop = false;
    std::thread m_writer;
};

}  // namespace spt
