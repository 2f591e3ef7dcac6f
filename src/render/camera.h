// Pinhole camera: position, look-at point, up vector and vertical field of view.
#pragma once
#include <cmath>

#include "core/vec3.h"
#include "geometry/ray.h"

namespace spt {

struct CameraSpec {
    Vec3 position{0, 0, 3.5f};
    Vec3 look_at{0, 0, 0};
    Vec3 up{0, 1, 0};
    float vfov_degrees = 40.f;
};

class Camera {
public:
    Camera(const CameraSpec& spec, int width, int height) : m_origin(spec.position) {
        const Vec3 forward = normalize(spec.look_at - spec.position);
        const Vec3 right = normalize(cross(forward, spec.up));
        const Vec3 true_up = cross(right, forward);
        const float half_h = std::tan(0.5f * spec.vfov_degrees * kPi / 180.f);
        const float half_w = half_h * static_cast<float>(width) / static_cast<float>(height);
        m_forward = forward;
        m_right = right * (2.f * half_w / static_cast<float>(width));
        m_down = true_up * (-2.f * half_h / static_cast<float>(height));
        m_top_left = forward - right * half_w + true_up * half_h;
    }

    /// Ray through film position (x, y) in pixels, (0, 0) the top-left corner of the image.
    Ray generate_ray(float x, float y) const {
        return {m_origin, normalize(m_top_left + m_right * x + m_down * y), kInfinity};
    }

private:
    Vec3 m_origin, m_forward, m_right, m_down, m_top_left;
};

}  // namespace spt
