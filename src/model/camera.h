// Camera: position, look-at point, up vector, field of view along one image axis and
// handedness; a pinhole, or a thin lens (an aperture focused at a distance: depth of field).
#pragma once
#include <cmath>

#include "core/vec3.h"
#include "geometry/ray.h"
#include "model/aperture.h"

namespace spt {

/// The image axis a field of view spans: smaller and larger are the image's shorter and longer
/// sides (pbrt-v4's "fov" is along the shorter one), so they depend on the rendered size.
enum class FovAxis { vertical, horizontal, smaller, larger };

struct CameraSpec {
    CameraSpec() = default;
    /// A pinhole (the lens is set by its fields).
    CameraSpec(const Vec3& position_, const Vec3& look_at_, const Vec3& up_, float vfov_degrees_)
        : position(position_), look_at(look_at_), up(up_), fov_degrees(vfov_degrees_) {}

    Vec3 position{0, 0, 3.5f};
    Vec3 look_at{0, 0, 0};
    Vec3 up{0, 1, 0};
    /// Field of view along fov_axis of the image rendered.
    float fov_degrees = 40.f;
    FovAxis fov_axis = FovAxis::vertical;
    /// Image right = up × forward (pbrt-v4's camera space) instead of forward × up: the
    /// mirror image.
    bool left_handed = false;
    /// Thin lens: radius 0 is the pinhole. Points at focus_distance along the view axis
    /// (a plane parallel to the image) are sharp; others blur into the aperture's shape.
    Aperture aperture;
    float focus_distance = 1.f;
    /// Exposure interval: each path sample sees the scene at one time drawn uniformly in
    /// it, when something moves (motion blur); with open = close the image is that instant.
    float shutter_open = 0.f, shutter_close = 1.f;
};

class Camera {
public:
    /// motion_blur: the scene moves while the shutter is open (Effects::motion_blur).
    Camera(const CameraSpec& spec, int width, int height, bool motion_blur = false)
        : m_origin(spec.position), m_aperture(spec.aperture), m_focus_distance(spec.focus_distance),
          m_shutter_open(spec.shutter_open), m_shutter_span(spec.shutter_close - spec.shutter_open),
          m_motion_blur(motion_blur) {
        const Vec3 forward = normalize(spec.look_at - spec.position);
        const Vec3 right_handed = normalize(cross(forward, spec.up));
        const Vec3 true_up = cross(right_handed, forward);
        const Vec3 right = spec.left_handed ? -right_handed : right_handed;
        const FovAxis axis = spec.fov_axis == FovAxis::smaller  ? (width < height ? FovAxis::horizontal : FovAxis::vertical)
                             : spec.fov_axis == FovAxis::larger ? (width > height ? FovAxis::horizontal : FovAxis::vertical)
                                                                : spec.fov_axis;
        const float half_fov = std::tan(0.5f * spec.fov_degrees * kPi / 180.f);
        const float half_h =
            axis == FovAxis::vertical ? half_fov : half_fov * static_cast<float>(height) / static_cast<float>(width);
        const float half_w =
            axis == FovAxis::vertical ? half_h * static_cast<float>(width) / static_cast<float>(height) : half_fov;
        m_forward = forward;
        m_right = right * (2.f * half_w / static_cast<float>(width));
        m_down = true_up * (-2.f * half_h / static_cast<float>(height));
        m_top_left = forward - right * half_w + true_up * half_h;
        m_width = static_cast<float>(width);
        m_height = static_cast<float>(height);
        m_film_area = 4.f * half_w * half_h;
        m_lens_right = right;
        m_lens_up = true_up;
    }

    /// Ray through film position (x, y) in pixels, (0, 0) the top-left corner of the image.
    /// The pinhole's (the lens's centre, for a thin lens).
    Ray generate_ray(float x, float y) const {
        return {m_origin, normalize(m_top_left + m_right * x + m_down * y), kInfinity};
    }

    /// Whether the camera has an aperture (depth of field): then rays start on the lens.
    bool thin_lens() const { return m_aperture.radius > 0.f; }
    /// Whether each sample draws its own time in the shutter interval (motion blur).
    bool motion_blur() const { return m_motion_blur; }
    /// The time of a sample without motion blur.
    float shutter_open() const { return m_shutter_open; }
    /// The time for a uniform number u in [0, 1): uniform over the shutter interval.
    float shutter_time(float u) const { return m_shutter_open + u * m_shutter_span; }
    /// Thin lens: the point of the lens for two uniform numbers (uniform over the aperture).
    Vec3 lens_point(float u1, float u2) const {
        const AperturePoint a = m_aperture.sample(u1, u2);
        return m_origin + m_lens_right * a.x + m_lens_up * a.y;
    }
    /// Thin lens: the ray through film position (x, y) from the lens point for (u1, u2). All
    /// the rays of one film position meet on the focus plane, where the pinhole's ray
    /// through (x, y) crosses it (pbrt's thin lens).
    Ray generate_ray(float x, float y, float u1, float u2) const {
        const Vec3 lens = lens_point(u1, u2);
        const Vec3 focus = m_origin + (m_top_left + m_right * x + m_down * y) * m_focus_distance;
        return {lens, normalize(focus - lens), kInfinity};
    }

    // ---- The camera as the end of a light path (bidirectional transport) ----
    // The pinhole is a delta position; its directions are spread over the image plane at
    // distance 1, of area A = film_area(). Jittered pixel rays are uniform on that plane, so
    // their solid-angle density is 1/(A·cos³θ), and the importance We = 1/(A·cos⁴θ) makes a
    // light path's splats sum to spp × the pixel value over all light paths (see bdpt.h).
    // A thin lens is the same from each lens point: its rays are uniform on the focus plane
    // (area A·f² at distance f/cosθ along them), so the directional density is again
    // 1/(A·cos³θ); lens points are uniform (density 1/lens area) and We = 1/(A·lens area·cos⁴θ)
    // (pbrt-v3 PerspectiveCamera::We). A splat that samples its lens point divides We by that
    // density: importance() below is We × lens area, the pinhole's expression.

    const Vec3& origin() const { return m_origin; }
    const Vec3& forward() const { return m_forward; }
    float film_area() const { return m_film_area; }

    /// Film position (pixels) of the direction `d` from the pinhole (any length); false when
    /// the direction misses the image.
    bool raster_position(const Vec3& d, float& x, float& y) const {
        const float cos_theta = dot(d, m_forward);
        if (!(cos_theta > 0.f)) return false;
        const Vec3 v = d / cos_theta - m_top_left;  // on the plane at distance 1
        x = dot(v, m_right) / length_squared(m_right);
        y = dot(v, m_down) / length_squared(m_down);
        return x >= 0.f && x < m_width && y >= 0.f && y < m_height;
    }
    /// Film position (pixels) of the unit direction `d` leaving the lens at `lens` (a thin
    /// lens; the pinhole's when `lens` is its origin and the aperture is 0): where the ray
    /// crosses the focus plane, seen from the lens's centre. False when it misses the image.
    bool raster_position(const Vec3& lens, const Vec3& d, float& x, float& y) const {
        if (!thin_lens()) return raster_position(d, x, y);
        const float cos_theta = dot(d, m_forward);
        if (!(cos_theta > 0.f)) return false;
        const Vec3 focus = lens + d * (m_focus_distance / cos_theta);
        return raster_position(focus - m_origin, x, y);  // needs no unit vector
    }
    /// Importance We of a direction at angle θ to the view axis (inside the image).
    float importance(float cos_theta) const {
        const float c2 = cos_theta * cos_theta;
        return 1.f / (m_film_area * c2 * c2);
    }
    /// Solid-angle density of camera rays in a direction at angle θ (inside the image).
    float direction_pdf(float cos_theta) const {
        return 1.f / (m_film_area * cos_theta * cos_theta * cos_theta);
    }

private:
    Vec3 m_origin, m_forward, m_right, m_down, m_top_left;
    Vec3 m_lens_right, m_lens_up;  ///< unit axes of the lens plane
    Aperture m_aperture;
    float m_focus_distance = 1.f;
    float m_shutter_open = 0.f, m_shutter_span = 0.f;
    bool m_motion_blur = false;
    float m_width = 1.f, m_height = 1.f, m_film_area = 1.f;
};

}  // namespace spt
