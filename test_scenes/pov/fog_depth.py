"""Planar depth of an unmodified POV-Ray scene from fog passes (docs/platform_notes.md, POV-Ray).

A wrapper #includes the scene and adds fog { distance D color rgb C }. Constant fog mixes a
ray's colour P as P t + C (1 - t), t = exp(-d / D), d the distance along the ray, so the
render with C = 1 minus the one with C = 0 is 1 - t whatever P is; d = -D ln(1 - diff).
"""
import math

import numpy as np

from povray_runner import Refusal, read

FIRST_FOG_DISTANCE = 10.0  # scene units; the ladder moves up and down from here
LADDER = 4.0               # ratio between successive fog distances
LADDER_STEPS = 10          # at most this many steps up or down: 4^10 ~ 1e6 times the first
SKY_FOG_DISTANCE = 1e7     # beyond any scene's depths, far below POV-Ray's background distance
FOV_CHECK_DEG = 0.05       # at 64 pixels wide and more (noise measured: <= 0.016 deg at 64x48)


def fog_pass(pov, distance, colour):
    # Secondary rays (reflection, refraction, transmission) are cut with adc_bailout 1 (every
    # secondary ray weighs < 1): only the first surface sees the fog, as the depth must.
    sdl = (f"fog {{ distance {distance!r} color rgb {colour} }}\n"
           "global_settings { adc_bailout 1 }\n")
    log, path = pov.run(sdl, ["-A", "+Q9"], f"depth pass (fog rgb {colour}, distance {distance:g})")
    if "Camera is inside a non-hollow object" in " ".join(log.split()):
        raise Refusal("POV-Ray: \"Camera is inside a non-hollow object. Fog and participating media may not work "
                      "as expected.\" The depth pass relies on fog: make that object hollow")
    return read(path)


def measure_gamma(black, white, grey):
    """POV-Ray 3.7 mixes colours in the scene's assumed_gamma space and writes EXR as its linear
    decoding, value^g. With fog colours 0, 1 and 0.5 the working-space values satisfy
    grey^(1/g) = (black^(1/g) + white^(1/g)) / 2; solve for g where that is well conditioned."""
    ok = well_conditioned(black, white) & (grey > black + 0.05)
    if ok.sum() < 10:
        return None
    b, w, m = black[ok], white[ok], grey[ok]
    lo, hi = np.full(b.shape, 0.2), np.full(b.shape, 5.0)
    for _ in range(60):  # f(g) = m^(1/g) - (b^(1/g) + w^(1/g))/2 changes sign once on [0.2, 5]
        g = (lo + hi) / 2
        f = m ** (1 / g) - (b ** (1 / g) + w ** (1 / g)) / 2
        flo = m ** (1 / lo) - (b ** (1 / lo) + w ** (1 / lo)) / 2
        same = np.sign(f) == np.sign(flo)
        lo, hi = np.where(same, g, lo), np.where(same, hi, g)
    return float(np.median((lo + hi) / 2))


def surfaces_lit(pov):
    """Pixels that see a surface with some colour: a black fog of a distance far beyond any
    scene (1e7 units) leaves surfaces nearly untouched but blacks out exactly the rays that
    hit nothing (POV-Ray puts the background at ~1e10). Unlit surfaces read 0 too, so this
    tells "certainly a surface", not "certainly sky"."""
    sdl = f"fog {{ distance {SKY_FOG_DISTANCE!r} color rgb 0 }}\n"
    return read(pov.run(sdl, ["-A", "+Q9"], "sky pass")[1]).max(axis=-1) > 0


def well_conditioned(black, white):
    return (white - black > 0.2) & (white < 0.999)


def ray_distance(black, white, distance, gamma):
    """(d, u): ray distance d = -D ln(1 - diff) from white - black = 1 - exp(-d/D) (channel
    mean, working space), and u = d / D."""
    diff = (white ** (1 / gamma) - black ** (1 / gamma)).mean(axis=-1)
    t = np.clip(1 - diff, 1e-12, 1)
    u = -np.log(t)
    return u * distance, u


def depth_passes(pov, first_distance):
    """Ray distance per pixel from a ladder of fog distances: each pixel takes the pass with
    d/D nearest 1, where half-float rounding costs least (relative error ~ 2^-11 e^u / u)."""
    passes = {}

    def add(distance):
        black, white = fog_pass(pov, distance, 0), fog_pass(pov, distance, 1)
        passes[distance] = (black, white)

    add(first_distance)
    sky_u = -math.log(2 ** -10)  # t below 2^-10 (~7 D): nothing finite resolved
    lit = surfaces_lit(pov)

    # The ladder's range with gamma 1 (its thresholds are coarse); the gamma is measured after.
    # Up while pixels remain beyond u = 2.5 that a step can still improve: resolved ones (u <
    # sky_u) or lit ones not resolved yet (a surface farther out; unlit unresolved pixels are
    # sky). Down while pixels sit below u = 0.4.
    for _ in range(LADDER_STEPS):
        top = max(passes)
        u = ray_distance(*passes[top], top, 1.0)[1]
        if not ((u > 2.5) & ((u < sky_u) | lit)).any():
            break
        add(top * LADDER)
    for _ in range(LADDER_STEPS):
        bottom = min(passes)
        u = ray_distance(*passes[bottom], bottom, 1.0)[1]
        if not ((u < 0.4) & (u > 0)).any():
            break
        add(bottom / LADDER)
    # Gamma from a grey fog at the distance that resolves the most pixels.
    chosen = max(passes, key=lambda D: int(well_conditioned(*passes[D]).any(axis=-1).sum()))
    gamma = measure_gamma(*passes[chosen], fog_pass(pov, chosen, 0.5))
    if gamma is None:
        if any(well_conditioned(*p).any() for p in passes.values()):
            raise Refusal("cannot measure the scene's assumed_gamma from the fog passes")
        gamma = 1.0  # nothing but sky (and fog-saturated surfaces): the gamma changes nothing
    est = {D: ray_distance(b, w, D, gamma) for D, (b, w) in passes.items()}
    distances = sorted(est)
    d_all = np.stack([est[D][0] for D in distances])
    u_all = np.stack([est[D][1] for D in distances])
    cost = np.where(u_all > 0, np.exp(u_all) / np.maximum(u_all, 1e-12), np.inf)
    best = np.argmin(cost, axis=0)
    d = np.take_along_axis(d_all, best[None], 0)[0]
    sky = u_all[-1] >= sky_u
    # Consistency: where two passes both resolve a pixel well, they must agree; they do not
    # when shading depends on the fog (the scene's own fog or media, light through surfaces).
    worst = 0.0
    for k in range(len(distances) - 1):
        both = (u_all[k] > 0.3) & (u_all[k] < 3) & (u_all[k + 1] > 0.3) & (u_all[k + 1] < 3)
        if both.sum() > 10:
            worst = max(worst, float(np.median(np.abs(d_all[k][both] / d_all[k + 1][both] - 1))))
    if worst > 0.01:
        raise Refusal(f"the depth passes disagree (median {worst:.1%} between fog distances): the scene's "
                      "colours change with the added fog (its own fog or media?); depth would be wrong")
    if (d[~sky] <= 0).any():
        raise Refusal("the added fog does not reach some surfaces (is the camera inside a non-hollow object?)")
    return d, sky, gamma, distances


def check_camera(pov, camera, width, height, nearest, gamma):
    """Check the camera read from the text against the one POV-Ray renders with: a black plane
    across the view axis at eps, half the nearest planar depth (so before every pixel's first
    hit), in a white fog of distance eps: every pixel's planar depth must come back as eps."""
    eps = 0.5 * nearest
    axis = camera.direction / np.linalg.norm(camera.direction)
    offset = float(axis @ camera.location) + eps
    n = ", ".join(repr(float(-c)) for c in axis)
    sdl = (f"plane {{ <{n}>, {-offset!r} hollow no_shadow pigment {{ rgb 0 }}\n"
           "  finish { ambient 0 diffuse 0 specular 0 phong 0 reflection 0 } }\n"
           f"fog {{ distance {eps!r} color rgb 1 }}\n"
           "global_settings { adc_bailout 1 }\n")
    white = read(pov.run(sdl, ["-A", "+Q9"], "camera check")[1])
    d, _ = ray_distance(np.zeros_like(white), white, eps, gamma)
    cos_model, cos_seen = camera.cosines(width, height), np.clip(eps / d, 1e-6, 1)
    offset_error = float(np.median(np.abs(d * cos_model / eps - 1)))
    # The field: tan^2 of each ray's angle to the axis scales as 1/|D|^2; fit the scale k
    # (tan^2 seen = k tan^2 model) and compare the horizontal fov it implies.
    t2_model, t2_seen = 1 / cos_model ** 2 - 1, 1 / cos_seen ** 2 - 1
    k = float((t2_model * t2_seen).sum() / (t2_model ** 2).sum())
    fov = camera.hfov_deg()
    fov_seen = math.degrees(2 * math.atan(math.tan(math.radians(fov) / 2) * math.sqrt(k)))
    if offset_error > 2e-3 or abs(fov_seen - fov) > FOV_CHECK_DEG * max(1, 64 / width):
        raise Refusal(f"the camera read from the scene's text does not match the one POV-Ray renders with (a test "
                      f"plane's planar depth is off by {offset_error:.2%}; fov {fov:.3f} deg read, {fov_seen:.3f} "
                      "deg seen)")
    return offset_error, fov_seen
