"""A light and a BSDF written with NumPy, each with a wrong twin.

The light: a sphere light seen from a reference point, sampled uniformly in the
cone of directions it subtends; sample(ref, u) returns (wi, pdf) per solid angle
and pdf(ref, wi) is the density of any direction. It is checked at a grid of
reference points, each a case on the sphere. The twin draws the cone's angle
uniformly instead of its cosine, a classic slip: its pdf no longer describes it.

The BSDF: Lambertian reflection, sampled cosine-weighted on wo's side; its twin
forgets the 1/pi of f, so that it reflects pi times the energy it receives.
"""

import functools

import numpy as np

import warpcheck as wc

CENTRE = np.array([0.0, 0.0, 2.0])
RADIUS = 1.6  # the light subtends a cone of half-angle acos(0.6) from the origin
# Reference points on the light's axis: the cone's rim then runs along the
# chi-square cells, and the test stays quick. A point off the axis,
# (0.7, -0.4, 0.2), passes too, in ~10 s: the quadrature of a rim that cuts
# the cells obliquely calls pdf some 50,000 times, each a Python call.
POINTS = [(0.0, 0.0, 0.0), (0.0, 0.0, 0.2)]


def _cone(ref):
    """The unit axis towards the light, cos of the cone's half-angle, and a frame:
    per reference point, computed once (the checks call pdf many times per point)."""
    return _cone_at(tuple(float(c) for c in ref))


@functools.lru_cache(maxsize=64)
def _cone_at(ref):
    to_centre = CENTRE - np.asarray(ref, dtype=np.float64)
    d = np.linalg.norm(to_centre)
    axis = to_centre / d
    cos_max = np.sqrt(1.0 - (RADIUS / d) ** 2)
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t = np.cross(axis, helper)
    t /= np.linalg.norm(t)
    return axis, cos_max, t, np.cross(axis, t)


def light_pdf(ref, wi):
    axis, cos_max, _, _ = _cone(ref)
    # Inside the cone, within 2^-22 of its rim: a float32 direction rounds its
    # cosine by about 2^-24 per coordinate, and the density's integral moves by
    # 2^-22 / (1 - cos_max) = 6e-7, inside chi2's 2^-20 normalisation allowance.
    inside = wi.astype(np.float64) @ axis >= cos_max - 2**-22
    return np.where(inside, 1.0 / (2 * np.pi * (1.0 - cos_max)), 0.0)


def _light_sample(ref, u, uniform_angle):
    axis, cos_max, t, b = _cone(ref)
    u = u.astype(np.float64)
    if uniform_angle:  # the twin's bug
        cos_theta = np.cos(u[:, 0] * np.arccos(cos_max))
    else:
        cos_theta = 1.0 - u[:, 0] * (1.0 - cos_max)
    sin_theta = np.sqrt(np.maximum(0.0, 1.0 - cos_theta**2))
    phi = 2 * np.pi * u[:, 1]
    wi = (np.outer(sin_theta * np.cos(phi), t) + np.outer(sin_theta * np.sin(phi), b) + np.outer(cos_theta, axis))
    wi = wi.astype(np.float32)
    return wi, light_pdf(ref, wi)


def light_sample(ref, u):
    return _light_sample(ref, u, False)


def light_sample_uniform_angle(ref, u):
    return _light_sample(ref, u, True)


RADIANCE = 2.0


def light_radiance(ref, wi):
    """The light's own intersection: its radiance along wi, 0 where the ray misses it."""
    return np.where(light_pdf(ref, wi) > 0, RADIANCE, 0.0)


def _with_radiance(sample):
    def sample_with_l(ref, u):
        wi, pdf = sample(ref, u)
        return wi, pdf, np.full(len(wi), RADIANCE)
    return sample_with_l


REFLECTANCE = 0.8


def _same_side(wo, wi):
    return wo[..., 2] * wi[..., 2] > 0


def lambert_f(wo, wi):
    return np.where(_same_side(wo, wi), REFLECTANCE / np.pi, 0.0)


def lambert_f_without_pi(wo, wi):
    return np.where(_same_side(wo, wi), REFLECTANCE, 0.0)


def lambert_pdf(wo, wi):
    return np.where(_same_side(wo, wi), np.abs(wi[:, 2]) / np.pi, 0.0)


def _lambert_sample(wo, uc, u, f):
    del uc  # one lobe: the lobe choice is not used
    r = np.sqrt(u[:, 0].astype(np.float64))
    phi = 2 * np.pi * u[:, 1]
    z = np.sqrt(np.maximum(0.0, 1.0 - u[:, 0]))
    z = np.where(wo[2] < 0, -z, z)
    wi = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1).astype(np.float32)
    wo_rows = np.broadcast_to(wo, wi.shape)
    return wi, f(wo_rows, wi), lambert_pdf(wo_rows, wi)


def lambert_sample(wo, uc, u):
    return _lambert_sample(wo, uc, u, lambert_f)


def lambert_sample_without_pi(wo, uc, u):
    return _lambert_sample(wo, uc, u, lambert_f_without_pi)


def _hash_unit(*arrays):
    """A uniform number in [0, 1) per row from the float32 bits of the arrays' columns, in
    order (a layered BSDF's walk hashes wo and wi so that a pair always gets the same estimate)."""
    h = np.full(len(arrays[0]), 2166136261, dtype=np.uint64)
    for a in arrays:
        bits = np.ascontiguousarray(a, dtype=np.float32).view(np.uint32).astype(np.uint64)
        for column in range(bits.shape[1]):
            h = ((h ^ bits[:, column]) * np.uint64(16777619)) & np.uint64(0xFFFFFFFF)
    h ^= h >> np.uint64(16)
    h = (h * np.uint64(0x7FEB352D)) & np.uint64(0xFFFFFFFF)
    h ^= h >> np.uint64(15)
    h = (h * np.uint64(0x846CA68B)) & np.uint64(0xFFFFFFFF)
    h ^= h >> np.uint64(16)
    return (h >> np.uint64(8)).astype(np.float64) / 2.0**24


def noisy_lambert_f(wo, wi):
    """An unbiased one-sample estimate of the Lambertian's f: R/pi times 2h, h uniform in [0, 1)."""
    return lambert_f(wo, wi) * 2.0 * _hash_unit(wo, wi)


def _noisy_sample(asymmetry):
    def sample(wo, uc, u):
        wi, _, pdf = _lambert_sample(wo, uc, u, lambert_f)
        wo_rows = np.broadcast_to(wo, wi.shape)
        return wi, lambert_f(wo_rows, wi) * 2.0 * uc * asymmetry(wo_rows, wi), pdf
    return sample


def _one_way(wo, wi):
    """1 + 0.2 (|cos theta_o| - |cos theta_i|): a factor that is not symmetric in its arguments."""
    return 1.0 + 0.2 * (np.abs(wo[:, 2]) - np.abs(wi[:, 2]))


def stochastic_bsdfs():
    """A Lambertian whose f is a noisy estimate (stochastic=True: bsdf_expectation judges it in
    expectation), and its twin whose f and weights carry a factor that is not symmetric in wo and
    wi: its weights agree with its f in expectation, but it is not reciprocal."""
    correct = wc.Bsdf("numpy_noisy_lambert", _noisy_sample(lambda wo, wi: 1.0), f=noisy_lambert_f, pdf=lambert_pdf,
                      theta_o=[45], params={"R": REFLECTANCE}, stochastic=True,
                      description="Lambertian, f and weights unbiased one-sample estimates")
    wrong = wc.Bsdf("numpy_noisy_lambert_one_way", _noisy_sample(_one_way),
                    f=lambda wo, wi: noisy_lambert_f(wo, wi) * _one_way(wo, wi), pdf=lambert_pdf, theta_o=[45],
                    params={"R": REFLECTANCE}, stochastic=True,
                    description="f and weights times 1 + 0.2 (|cos theta_o| - |cos theta_i|): not reciprocal")
    return correct, wrong


def lights():
    correct = wc.Light("numpy_sphere_light", light_sample, pdf=light_pdf, points=POINTS,
                       description="sphere light sampled uniformly in the cone it subtends")
    wrong = wc.Light("numpy_sphere_light_uniform_angle", light_sample_uniform_angle, pdf=light_pdf,
                     points=POINTS[:1], description="the cone's angle drawn uniformly instead of its cosine")
    return correct, wrong


def lights_with_radiance():
    """The same light with its radiance and its own intersection L(ref, wi), seen from a
    surface whose normal is +z: a light case, which the light checks take. Its twin
    draws the cone's angle uniformly, which chi2 and the irradiance estimate see."""
    correct = wc.Light("numpy_sphere_light_l", _with_radiance(light_sample), pdf=light_pdf, L=light_radiance,
                       normal=(0, 0, 1), points=POINTS[:1], description="sphere light with its radiance")
    wrong = wc.Light("numpy_sphere_light_l_uniform_angle", _with_radiance(light_sample_uniform_angle), pdf=light_pdf,
                     L=light_radiance, normal=(0, 0, 1), points=POINTS[:1],
                     description="the cone's angle drawn uniformly instead of its cosine")
    return correct, wrong


def bsdfs():
    correct = wc.Bsdf("numpy_lambert", lambert_sample, f=lambert_f, pdf=lambert_pdf, theta_o=[0, 45, 80],
                      params={"R": REFLECTANCE}, description="Lambertian reflection, cosine-weighted sampling")
    wrong = wc.Bsdf("numpy_lambert_without_pi", lambert_sample_without_pi, f=lambert_f_without_pi, pdf=lambert_pdf,
                    theta_o=[45], params={"R": REFLECTANCE}, description="f without its 1/pi")
    return correct, wrong


def light_area_pdf(ref, wi):
    """The light's density per unit AREA of the sphere at the point wi hits (pdf times |cos| at
    the light over the squared distance): the bug of an area pdf in a solid-angle MIS sum."""
    p = np.asarray(ref, dtype=np.float64)
    w = wi.astype(np.float64)
    w /= np.linalg.norm(w, axis=1, keepdims=True)
    to_centre = CENTRE - p
    b = w @ to_centre
    disc = np.maximum(b * b - (to_centre @ to_centre - RADIUS**2), 0.0)
    t = b - np.sqrt(disc)
    hit = (light_pdf(ref, wi) > 0) & (t > 0)
    normal = (t[:, None] * w - to_centre) / RADIUS
    cos_light = np.abs(np.sum(normal * w, axis=1))
    return np.where(hit, light_pdf(ref, wi) * cos_light / np.maximum(t * t, 1e-300), 0.0)


def mis_parts():
    """The Lambertian at 45 degrees and the sphere light with L seen from the origin (normal +z)."""
    bsdf = wc.Bsdf("numpy_lambert", lambert_sample, f=lambert_f, pdf=lambert_pdf, theta_o=[45],
                   params={"R": REFLECTANCE}, description="Lambertian reflection")
    light = wc.Light("numpy_sphere_light_l", _with_radiance(light_sample), pdf=light_pdf, L=light_radiance,
                     normal=(0, 0, 1), points=POINTS[:1], description="sphere light with its radiance")
    return bsdf, light


def mis_cases():
    """A renderer's direct lighting at a diffuse point under the sphere light: the Lambertian
    and the light combined by the power heuristic, with the pdfs its MIS code evaluates given
    as NumPy functions (here the cases' own). The twin's MIS sum takes the light's density per
    unit area of the light for its density per solid angle."""
    bsdf, light = mis_parts()
    correct = wc.Mis("numpy_mis_lambert_sphere", bsdf, [light], bsdf_mis_pdf=lambert_pdf, light_mis_pdfs=[light_pdf],
                     description="Lambertian and a sphere light, power heuristic")
    wrong = wc.Mis("numpy_mis_area_pdf", bsdf, [light], light_mis_pdfs=[light_area_pdf],
                   description="the MIS sum takes the light's area pdf for its solid-angle pdf")
    return correct, wrong


if __name__ == "__main__":
    print(wc.run([*lights(), *bsdfs(), *mis_cases()], samples=100_000).table())
