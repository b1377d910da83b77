// Floats in an interval [a,b) or [a,b]: the two lerps renderers write, and a
// sampler that returns every float of the interval with its exact probability.
//
// Reference measure: a uniform real of [a,b) rounded down (towards -inf) to a
// float, so P(x) = (next_float_up(x) - x) / (b - a) for every float x of [a,b).
// For the closed [a,b] it is the uniform real rounded to nearest: the two end
// points get half a spacing each.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "sampling/float_bits.h"
#include "sampling/unit_float.h"

namespace warpcheck {

/// a + t (b - a). Monotone in t (one rounding of a monotone product, then a
/// monotone sum), but b - a rounds, so t < 1 can give b (and with b - a
/// rounded up, even slightly more); t = 0 gives a exactly.
constexpr float lerp_offset(float t, float a, float b) { return a + t * (b - a); }

/// (1 - t) a + t b. Exact at both ends (t = 0 gives a, t = 1 gives b), but two
/// products rounded separately are not monotone in t: the result can step down.
constexpr float lerp_blend(float t, float a, float b) { return (1.0f - t) * a + t * b; }

/// A lerp over [a,b) with t in [0,1): sample, pdf and inverse. The density is
/// the uniform 1/(b-a); the float result only approximates it (see the two forms).
struct LerpInterval {
    enum class Form { Offset, Blend };

    float a = 0.0f;
    float b = 1.0f;
    Form form = Form::Offset;

    /// Throws std::invalid_argument unless a and b are finite, a < b, and b - a
    /// is finite in float.
    LerpInterval(float lo, float hi, Form f) : a(lo), b(hi), form(f) {
        if (!std::isfinite(lo) || !std::isfinite(hi)) throw std::invalid_argument("lerp interval: a and b must be finite");
        if (!(lo < hi)) throw std::invalid_argument("lerp interval: needs a < b, got a = " + std::to_string(lo) +
                                                    ", b = " + std::to_string(hi));
        if (!std::isfinite(hi - lo)) throw std::invalid_argument("lerp interval: b - a overflows float");
    }

    float sample(float t) const { return form == Form::Offset ? lerp_offset(t, a, b) : lerp_blend(t, a, b); }
    /// 1/(b-a) inside [a,b], 0 outside.
    float pdf(float x) const {
        return x >= a && x <= b ? static_cast<float>(1.0 / (static_cast<double>(b) - static_cast<double>(a))) : 0.0f;
    }
    /// (x - a) / (b - a) in double, rounded to float: the t that maps to x
    /// (up to the rounding of sample).
    float invert(float x) const {
        return static_cast<float>((static_cast<double>(x) - a) / (static_cast<double>(b) - static_cast<double>(a)));
    }
};

/// Every float of [a,b) (or [a,b]) with its exact probability, for any finite
/// a < b (a <= b when closed), including intervals that span zero and the
/// denormals. `sample(rng)` takes a callable returning uint64_t (or uint32_t).
///
/// Two paths, chosen at construction:
/// - Narrow: when (b - a) is at most 2^40 times the finest float spacing s in
///   the interval (always so when a and b share a binade), every float is a
///   multiple of s: draw r uniform in [0, N), N = (b-a)/s, exactly (one
///   division: r = w / floor(2^64 / N), rejecting the top 2^64 mod N words, a
///   fraction below 2^-24), and round a + r s down to a float. Expected draws
///   1 + 2^-24 at most, whatever the width: a narrow interval is as cheap as
///   any other.
/// - Wide: Walker's exponent count over [0, 2^(E+1)) (or the symmetric range
///   when the interval spans zero) with rejection of what falls outside [a,b).
///   The interval then covers at least 17 binades of the range, so the
///   acceptance is above 1/2 (1/4 when it spans zero).
/// Both paths map the first word monotonically to x, rotated so that every
/// rejected first word lies above every accepted one; `invert(x)` gives
/// the smallest first word that produces x.
///
/// Termination: at most kMaxAttempts = 256 rejections (probability below
/// 2^-100 in the worst case); then `a` is returned. Each attempt draws at most
/// 6 words (the narrow path: exactly 1).
class UniformFloatInterval {
public:
    static constexpr int kMaxAttempts = 256;

    /// Half-open [a,b) (closed = false) or closed [a,b]. Throws
    /// std::invalid_argument for non-finite bounds, a > b, or a == b when open.
    UniformFloatInterval(float lo, float hi, bool closed = false) : a_(lo), b_(hi), closed_(closed) {
        if (!std::isfinite(lo) || !std::isfinite(hi))
            throw std::invalid_argument("uniform float interval: a and b must be finite");
        if (closed ? !(lo <= hi) : !(lo < hi))
            throw std::invalid_argument("uniform float interval: needs a " + std::string(closed ? "<=" : "<") +
                                        " b, got a = " + std::to_string(lo) + ", b = " + std::to_string(hi));
        if (lo == hi) {
            degenerate_ = true;
            return;
        }
        if (a_ == 0.0f) a_ = 0.0f;  // -0 -> +0: the same point, and +0 is the first float of [0, b)
        set_up_narrow_or_wide();
    }

    float a() const { return a_; }
    float b() const { return b_; }
    bool closed() const { return closed_; }
    /// Whether the narrow (direct) path is used.
    bool narrow() const { return narrow_; }

    template <typename Rng>
    float sample(Rng& rng) const {
        if (degenerate_) return a_;
        float x = a_;
        for (int attempt = 0; attempt < kMaxAttempts; ++attempt) {
            const uint64_t w = detail::draw_u64(rng) + offset_;  // rotation: rejected words come last
            bool accepted;
            x = map_first_word(w, rng, accepted);
            if (accepted) break;
            x = a_;
        }
        // [a,b]: move half of each float's mass to its upper neighbour, which
        // turns "rounded down" into "rounded to nearest" (b gets half a spacing).
        if (closed_ && (detail::draw_u64(rng) >> 63) != 0) x = next_float_up(x);
        return x;
    }

    /// The uniform density 1/(b-a) inside the interval, 0 outside (for the
    /// degenerate closed [a,a], a point mass: infinity at a).
    float pdf(float x) const {
        const bool inside = closed_ ? (x >= a_ && x <= b_) : (x >= a_ && x < b_);
        if (!inside) return 0.0f;
        if (degenerate_) return std::numeric_limits<float>::infinity();
        return static_cast<float>(1.0 / (static_cast<double>(b_) - static_cast<double>(a_)));
    }

    /// The CDF at x, (x - a)/(b - a) in double: the fraction of mass below x.
    double cdf(float x) const {
        if (degenerate_) return x < a_ ? 0.0 : 1.0;
        const double t = (static_cast<double>(x) - a_) / (static_cast<double>(b_) - static_cast<double>(a_));
        return t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    }

    /// The smallest first random word with which sample returns x, for x in
    /// [a,b) of the half-open sampler (the closed sampler draws one more word).
    /// Exact everywhere on the narrow path; on the wide path exact for
    /// magnitudes above 2^(E-39) (E: the top binade of the range), below which
    /// further words decide as well (probability 2^-40).
    uint64_t invert(float x) const {
        if (degenerate_) return 0;
        if (narrow_) {
            const int64_t units = float_in_units(x);
            return static_cast<uint64_t>(units - a_units_) * divisor_;
        }
        return raw_first_word(x) - offset_;
    }

private:
    // --- the narrow path: a + r s, r uniform in [0, N) --------------------

    // x / s as a signed integer (x a float of the interval, so a multiple of s).
    int64_t float_in_units(float x) const {
        const uint64_t m = detail::float_to_scaled_u64(std::fabs(x), -spacing_exponent_);
        return x < 0.0f ? -static_cast<int64_t>(m) : static_cast<int64_t>(m);
    }

    // Rounds z s down (towards -inf) to a float; |z| < 2^63.
    float units_to_float_down(int64_t z) const {
        if (z >= 0) return detail::scaled_u64_to_float_down(static_cast<uint64_t>(z), spacing_exponent_);
        // Negative: round the magnitude up. Truncate to 24 significant bits; if
        // anything was cut, the next float up in magnitude.
        const auto m = static_cast<uint64_t>(-z);
        const float down = detail::scaled_u64_to_float_down(m, spacing_exponent_);
        const bool exact = detail::float_to_scaled_u64(down, -spacing_exponent_) == m;
        return -(exact ? down : next_float_up(down));
    }

    // The finest spacing among the floats of [a,b]: that of the end point nearest
    // zero (upwards in magnitude), 2^-149 when the interval contains zero.
    static int spacing_exponent_at(float magnitude) {
        const int biased = float_biased_exponent(magnitude);
        return (biased == 0 ? 1 : biased) - kFloatExponentBias - kFloatSignificandBits;
    }

    // Binade index e of a positive float (x in [2^e, 2^(e+1))), -127 for denormals.
    static int binade(float magnitude) {
        const int biased = float_biased_exponent(magnitude);
        return biased == 0 ? -127 : biased - kFloatExponentBias;
    }

    void set_up_narrow_or_wide() {
        if (a_ >= 0.0f) {
            kind_ = Kind::Positive;
            spacing_exponent_ = spacing_exponent_at(a_);
            top_ = binade(next_float_down(b_));
        } else if (b_ <= 0.0f) {
            kind_ = Kind::Negative;
            spacing_exponent_ = spacing_exponent_at(-b_);
            top_ = binade(next_float_down(-a_));  // magnitudes lie in (0, 2^(top+1)]
        } else {
            kind_ = Kind::Both;
            spacing_exponent_ = -149;
            top_ = std::max(binade(next_float_down(-a_)), binade(next_float_down(b_)));
        }
        // N = (b - a)/s fits 40 bits iff both end points do (then |z| < 2^41).
        const int64_t span_limit = int64_t{1} << 40;
        const int limit_exponent = spacing_exponent_ + 40;  // |x| < 2^limit_exponent <=> |x|/s < 2^40
        const bool fits = std::fabs(a_) < std::ldexp(1.0f, limit_exponent) &&
                          std::fabs(b_) < std::ldexp(1.0f, limit_exponent);
        if (fits) {
            a_units_ = float_in_units(a_);
            const int64_t n = float_in_units(b_) - a_units_;
            if (n <= span_limit) {
                narrow_ = true;
                count_ = static_cast<uint64_t>(n);
                // floor(2^64 / N); N = 1 would need 2^64 and is kept as 0 (r is always 0).
                divisor_ = std::numeric_limits<uint64_t>::max() / count_;
                if (count_ == 1) divisor_ = 0;
                else if (std::numeric_limits<uint64_t>::max() % count_ == count_ - 1) ++divisor_;
                offset_ = 0;
                return;
            }
        }
        narrow_ = false;
        offset_ = 0;
        // Rotate so the first word of a is 0: rejected words come after all
        // accepted ones. Where a lies below the one-word part of the range (|a|
        // tiny against 2^top, decided by further words), start at the first
        // word of zero instead; the rare words that reach below zero then sit at
        // the very top, among the rejected ones.
        const float reach = std::ldexp(1.0f, top_ - 39);  // one word decides above this magnitude
        if (kind_ == Kind::Positive) {
            offset_ = a_ >= reach ? raw_first_word(a_) : 0;
        } else if (kind_ == Kind::Negative || -a_ > reach) {
            offset_ = raw_first_word(a_);
        } else {
            offset_ = uint64_t{1} << 63;  // the first word of +0
        }
    }

    template <typename Rng>
    float map_first_word(uint64_t w, Rng& rng, bool& accepted) const {
        float x;
        if (narrow_) {
            const uint64_t r = divisor_ == 0 ? 0 : w / divisor_;
            accepted = r < count_;
            if (!accepted) return a_;
            x = units_to_float_down(a_units_ + static_cast<int64_t>(r));
            return x;
        }
        switch (kind_) {
            case Kind::Positive: x = detail::sample_below_power_of_two(top_, w, 64, rng); break;
            case Kind::Negative: x = -next_float_up(detail::sample_below_power_of_two(top_, ~w, 64, rng)); break;
            case Kind::Both:
            default: {
                const uint64_t half = uint64_t{1} << 63;
                x = w >= half ? detail::sample_below_power_of_two(top_, w - half, 63, rng)
                              : -next_float_up(detail::sample_below_power_of_two(top_, half - 1 - w, 63, rng));
                break;
            }
        }
        accepted = x >= a_ && x < b_;
        return x;
    }

    // The smallest (unrotated) first word that maps to x on the wide path. For a
    // negative x = -next_up(m), m's words form a block [V0, V1); its words map
    // in reverse, so the smallest w is the image of V1 - 1. Below the one-word
    // reach the first word is m's significand (Walker's continuation), unique.
    uint64_t raw_first_word(float x) const {
        const int bits = kind_ == Kind::Both ? 63 : 64;
        const float reach = std::ldexp(1.0f, top_ + 24 - bits);
        if (x >= 0.0f) {
            const uint64_t v = x < reach ? float_significand(x) : detail::below_power_of_two_first_word(top_, x, bits);
            return kind_ == Kind::Both ? (uint64_t{1} << 63) + v : v;
        }
        const float magnitude = -x;  // = next_up(m)
        const float m = next_float_down(magnitude);
        const bool at_top = magnitude >= std::ldexp(1.0f, top_ + 1);
        const uint64_t last_v = m < reach ? float_significand(m)
                                : at_top  ? (bits == 64 ? ~uint64_t{0} : (uint64_t{1} << 63) - 1)
                                          : detail::below_power_of_two_first_word(top_, magnitude, bits) - 1;
        return kind_ == Kind::Both ? (uint64_t{1} << 63) - 1 - last_v : ~last_v;
    }

    enum class Kind { Positive, Negative, Both };

    float a_;
    float b_;
    bool closed_;
    bool degenerate_ = false;
    bool narrow_ = false;
    Kind kind_ = Kind::Positive;
    int spacing_exponent_ = 0;  // s = 2^spacing_exponent_
    int top_ = 0;  // wide path: magnitudes in [0, 2^(top+1)) (positive) or (0, 2^(top+1)] (negative)
    int64_t a_units_ = 0;       // narrow path: a / s
    uint64_t count_ = 0;        // narrow path: N
    uint64_t divisor_ = 1;      // narrow path: floor(2^64 / N), 0 for N = 1
    uint64_t offset_ = 0;       // wide path: the rotation of the first word
};

}  // namespace warpcheck
