// Class 4 of issue 22: discontinuous densities and the quadrature's own error
// bound. (The triangle's jump along x + y = 1 is triangle_right in
// supports.cpp; the peaked cos^1000 is phong in quantised_outputs.cpp.)
//
// Rectangle area lights above the shading point, facing down, sampled by
// area (a point of the rectangle from u) and converted to solid angle, as
// every renderer does: pdf = dist^2 / (cos_light area), where the ray from the
// origin along w meets the light, and 0 elsewhere. Correct: the change of
// variables from area to solid angle, with cos_light = w.z for a light in the
// plane z = h facing -z. Hard: on the hemisphere the density jumps to 0 at the
// light's silhouette, which crosses the chi-square cells obliquely (the
// quadrature missed its accuracy rule at 10^6 samples and gave an ERROR); the
// re-intersection in float puts points sampled on the rectangle's edge just
// outside it (pdf 0 at a sampled direction, class 3).
// - rect_light: 0.8 x 0.8 at height 1, off the normal;
// - sliver_light: 0.002 x 1 at height 1, narrower than a chi-square cell (a
//   cell is 2 pi / 32 of azimuth): a sliver inside a cell was integrated as
//   0 while 108 samples landed there, and the ERROR hid that.
// Twins: the conversion without its cos factor (pdf dist^2 / area); a sliver
// whose sampled rectangle is 1.5 times as wide as the light its pdf describes.
#include <string>

#include "hard_warps.h"

namespace hard {
namespace {

using warpcheck::chi2::Domain;

struct RectLight {
    float x0, x1, y0, y1, height = 1;
    float sampled_x1 = x1;          // twin: a wider sampled rectangle
    bool forgets_cos = false;       // twin: pdf without the cos factor

    float area() const { return (x1 - x0) * (y1 - y0); }
    Vector3f sample(Point2f u) const {
        const Vector3f p{x0 + u.x * (sampled_x1 - x0), y0 + u.y * (y1 - y0), height};
        return normalize(p);
    }
    float pdf(Vector3f w) const {
        if (w.z <= 0) return 0;
        const float t = height / w.z;  // the distance to the light's plane along w
        const float x = t * w.x, y = t * w.y;
        if (x < x0 || x > x1 || y < y0 || y > y1) return 0;
        return forgets_cos ? t * t / area() : t * t / (w.z * area());
    }
};

void add_light(warpcheck::Registry& registry, const std::string& family, const std::string& description,
               RectLight light) {
    registry.add_case(warpcheck::make_warp_case(
        {.family = family, .description = description, .domain = Domain::hemisphere()}, light));
}

}  // namespace

void register_discontinuities(warpcheck::Registry& registry) {
    const RectLight rect{0.2f, 1.0f, -0.3f, 0.5f};
    add_light(registry, "rect_light", "0.8 x 0.8 rectangle light at z = 1 sampled by area, pdf in solid angle", rect);
    RectLight no_cos = rect;
    no_cos.forgets_cos = true;
    add_light(registry, "rect_light_forgets_cos", "the rectangle light whose pdf lacks the 1/cos_light", no_cos);
    mark_twin(registry, "rect_light_forgets_cos", "chi2", "pdf dist^2 / area without 1/cos_light");

    const RectLight sliver{0.4f, 0.402f, -0.5f, 0.5f};
    add_light(registry, "sliver_light", "0.002 x 1 rectangle light at z = 1, narrower than a chi-square cell", sliver);
    RectLight wide = sliver;
    wide.sampled_x1 = 0.403f;
    add_light(registry, "sliver_light_samples_outside", "the sliver sampled 1.5 times too wide", wide);
    mark_twin(registry, "sliver_light_samples_outside", "consistency,chi2",
              "a third of the samples fall outside the light, where the pdf is 0");
}

}  // namespace hard
