// Live previews: while the render runs, its unfinished image is rewritten under the outputs'
// partial names (so any viewer that reloads them shows the progress) and sent to a tev viewer.
// Driven by the rendering thread at pass boundaries, when no worker writes the film: reading
// it then changes nothing in the render.
#pragma once
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/tev_client.h"
#include "render/film.h"
#include "spectral/color_space.h"

namespace spt {

struct PreviewSettings {
    std::vector<std::string> outputs;  ///< final names; preview files go to their partial names
    std::optional<double> interval;    ///< seconds between preview files (nullopt: no files)
    std::optional<DisplayServerAddress> display_server;  ///< a tev viewer, or none
    ColorSpace space;                  ///< linear RGB sent to the viewer (the outputs' space)
    bool quiet = false;                ///< no "preview:" line (warnings are always printed)
};

/// Pass length the renderer should aim at (RenderSettings::pass_seconds) so that previews come
/// on time: half the interval (a preview is then at most 1.5 intervals after the last), one
/// second for a viewer without an interval; 0 (automatic passes) when nothing is previewed or
/// the interval is 0 (a preview after every pass, whatever its length).
double preview_pass_seconds(const PreviewSettings& settings);

class LivePreview {
public:
    /// Writes the film's image to these paths, atomically, all or nothing (throws on failure).
    using WriteImages = std::function<void(const std::vector<std::string>& paths, const Film& film)>;

    /// Says what will be previewed (stderr, unless quiet), connects to the display server and
    /// creates the image there. A viewer that cannot be reached is a one-line warning: the
    /// render goes on without it.
    LivePreview(PreviewSettings settings, WriteImages write, int width, int height);
    ~LivePreview();

    /// At a pass boundary: the preview files once `interval` seconds have passed since the
    /// last ones (or the start); the viewer with them, or after every pass without interval.
    /// A failure is a one-line warning and ends that kind of preview; the render goes on.
    void pass_completed(const Film& film);

    /// The render is over (finished or interrupted): the viewer is sent the last film.
    void render_ended(const Film& film);

    /// Once the finished images are written: removes the partial files this run wrote
    /// (an unfinished image from an earlier run is not this run's to remove).
    void remove_preview_files();

private:
    void write_files(const Film& film);
    void show(const Film& film);

    PreviewSettings m_settings;
    WriteImages m_write;
    std::vector<std::string> m_partial_names;
    std::string m_viewer_image;  ///< the name of the image in the viewer: the output's stem
    std::unique_ptr<TevClient> m_viewer;
    bool m_wrote_files = false;
    bool m_files_failed = false;  ///< a preview could not be written: no more are tried
    std::chrono::steady_clock::time_point m_last_files;
};

}  // namespace spt
