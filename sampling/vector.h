// Small value types that warps take and return. Plain aggregates of floats, so a
// warp written against them can be moved into any renderer's own vector types.
#pragma once

#include <cmath>

namespace warpcheck {

/// A point of the unit square (the usual input of a 2D warp) or of the plane.
struct Point2f {
    float x = 0.0f;
    float y = 0.0f;
    friend constexpr bool operator==(const Point2f&, const Point2f&) = default;
};

/// A direction or point in 3D. Directions use the shading frame: z is the normal.
struct Vector3f {
    float x = 0.0f;
    float y = 0.0f;
    float z = 0.0f;
    friend constexpr bool operator==(const Vector3f&, const Vector3f&) = default;
};

constexpr Vector3f operator+(Vector3f a, Vector3f b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Vector3f operator-(Vector3f a, Vector3f b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr Vector3f operator*(float s, Vector3f v) { return {s * v.x, s * v.y, s * v.z}; }
constexpr float dot(Vector3f a, Vector3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vector3f cross(Vector3f a, Vector3f b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vector3f v) { return std::sqrt(dot(v, v)); }
inline Vector3f normalize(Vector3f v) { return (1.0f / length(v)) * v; }

}  // namespace warpcheck
