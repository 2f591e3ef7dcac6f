// Preview files and the tev viewer: the film copied between passes, written by another thread.
#include "cli/live_preview.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "cli/output_names.h"

namespace spt {

namespace {

constexpr double kViewerPassSeconds = 1.0;

std::string join(const std::vector<std::string>& names) {
    std::string s;
    for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
    return s;
}

}  // namespace

double preview_pass_seconds(const PreviewSettings& s) {
    if (s.interval) return *s.interval / 2;
    return s.display_server ? kViewerPassSeconds : 0.0;
}

LivePreview::LivePreview(PreviewSettings settings, WriteImages write, int width, int height)
    : m_settings(std::move(settings)), m_write(std::move(write)), m_width(width), m_height(height),
      m_partial_names(partial_output_names(m_settings.outputs)),
      m_viewer_image(std::filesystem::path(m_settings.outputs.front()).stem().string()),
      m_last_preview(std::chrono::steady_clock::now()) {
    m_files_on = m_settings.interval.has_value();
    if (m_files_on && !m_settings.quiet)
        std::fprintf(stderr, "preview: %s every %g s\n", join(m_partial_names).c_str(),
                     *m_settings.interval);
    if (m_settings.display_server) {
        try {
            m_viewer = std::make_unique<TevClient>(*m_settings.display_server);
            m_viewer->create_image(m_viewer_image, width, height);
            m_viewer_on = true;
            if (!m_settings.quiet)
                std::fprintf(stderr, "preview: image '%s' on the display server %s\n",
                             m_viewer_image.c_str(), m_settings.display_server->describe().c_str());
        } catch (const std::runtime_error& e) {
            m_viewer.reset();
            std::fprintf(stderr, "pathtracer: warning: %s; rendering without it\n", e.what());
        }
    }
    if (m_files_on || m_viewer_on) m_writer = std::thread([this] { writer_loop(); });
}

LivePreview::~LivePreview() { stop_writer(); }

void LivePreview::pass_completed(const Film& film) {
    if (!m_files_on && !m_viewer_on) return;
    const auto now = std::chrono::steady_clock::now();
    const bool due = m_settings.interval
                         ? std::chrono::duration<double>(now - m_last_preview).count() >= *m_settings.interval
                         : true;  // a viewer without interval: every pass
    if (!due) return;
    const std::lock_guard lock(m_mutex);
    if (m_busy) return;  // the last preview is still being written: try at the next pass
    m_last_preview = now;
    m_job = film.save_state();  // the workers wait for this copy only
    m_busy = true;
    m_wake.notify_one();
}

void LivePreview::render_ended(const Film& film) {
    stop_writer();
    if (m_viewer_on) show(film);
}

void LivePreview::remove_preview_files() {
    if (!m_wrote_files) return;
    for (const std::string& name : m_partial_names) std::remove(name.c_str());
    m_wrote_files = false;
}

void LivePreview::writer_loop() {
    for (;;) {
        std::string state;
        {
            std::unique_lock lock(m_mutex);
            m_wake.wait(lock, [&] { return m_job || m_stop; });
            if (m_stop) return;  // a preview not yet started is stale: the final image follows
            state = std::move(*m_job);
            m_job.reset();
        }
        Film copy(m_width, m_height);
        copy.restore_state(state);
        if (m_files_on) {
            try {
                m_write(m_partial_names, copy);
                m_wrote_files = true;
            } catch (const std::exception& e) {
                m_files_on = false;
                std::fprintf(stderr, "pathtracer: warning: preview not written (%s); no more previews\n",
                             e.what());
            }
        }
        if (m_viewer_on) show(copy);
        const std::lock_guard lock(m_mutex);
        m_busy = false;
    }
}

void LivePreview::stop_writer() {
    if (!m_writer.joinable()) return;
    {
        const std::lock_guard lock(m_mutex);
        m_stop = true;
    }
    m_wake.notify_one();
    m_writer.join();
}

void LivePreview::show(const Film& film) {
    try {
        m_viewer->update_image(m_viewer_image, film.develop(m_settings.space));
    } catch (const std::exception& e) {
        m_viewer_on = false;
        std::fprintf(stderr, "pathtracer: warning: %s; rendering on without it\n", e.what());
    }
}

}  // namespace spt
