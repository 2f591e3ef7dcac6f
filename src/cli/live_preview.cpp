// Preview files and the tev viewer, at pass boundaries.
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
    : m_settings(std::move(settings)), m_write(std::move(write)),
      m_partial_names(partial_output_names(m_settings.outputs)),
      m_viewer_image(std::filesystem::path(m_settings.outputs.front()).stem().string()),
      m_last_files(std::chrono::steady_clock::now()) {
    if (m_settings.interval && !m_settings.quiet)
        std::fprintf(stderr, "preview: %s every %g s\n", join(m_partial_names).c_str(),
                     *m_settings.interval);
    if (!m_settings.display_server) return;
    const std::string address = m_settings.display_server->describe();
    try {
        m_viewer = std::make_unique<TevClient>(*m_settings.display_server);
        m_viewer->create_image(m_viewer_image, width, height);
        if (!m_settings.quiet)
            std::fprintf(stderr, "preview: image '%s' on the display server %s\n", m_viewer_image.c_str(),
                         address.c_str());
    } catch (const std::runtime_error& e) {
        m_viewer.reset();
        std::fprintf(stderr, "pathtracer: warning: %s; rendering without it\n", e.what());
    }
}

LivePreview::~LivePreview() = default;

void LivePreview::pass_completed(const Film& film) {
    bool files_due = false;
    if (m_settings.interval && !m_files_failed) {
        const auto now = std::chrono::steady_clock::now();
        files_due = std::chrono::duration<double>(now - m_last_files).count() >= *m_settings.interval;
        if (files_due) {
            m_last_files = now;
            write_files(film);
        }
    }
    if (files_due || !m_settings.interval) show(film);
}

void LivePreview::render_ended(const Film& film) { show(film); }

void LivePreview::remove_preview_files() {
    if (!m_wrote_files) return;
    for (const std::string& name : m_partial_names) std::remove(name.c_str());
    m_wrote_files = false;
}

void LivePreview::write_files(const Film& film) {
    try {
        m_write(m_partial_names, film);
        m_wrote_files = true;
    } catch (const std::runtime_error& e) {
        std::fprintf(stderr, "pathtracer: warning: preview not written (%s); no more previews\n",
                     e.what());
        m_files_failed = true;
    }
}

void LivePreview::show(const Film& film) {
    if (!m_viewer) return;
    try {
        m_viewer->update_image(m_viewer_image, film.develop(m_settings.space));
    } catch (const std::runtime_error& e) {
        m_viewer.reset();
        std::fprintf(stderr, "pathtracer: warning: %s; rendering on without it\n", e.what());
    }
}

}  // namespace spt
