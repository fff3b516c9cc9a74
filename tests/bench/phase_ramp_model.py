#!/usr/bin/env python3
"""The coded phases' residual noise on a uniform wall, computed rather than sampled
(docs/phase_codes.md, "Phase ramps across cells"): how the cell ramp's frequencies were chosen.

With one random phase Theta_c per cell, the residual at film pixel p is
    R_p = sum_{c != c'} exp(i (Theta_c - Theta_c')) W_cc'(p),
    W_cc'(p) = sum_m exp(2 pi i (sigma_cm - sigma_c'm)) B_p(s_cm, s_c'm),
B_p(s, t) the pixel's mean of a_s a_t* over its film points, so Var R_p = sum_{c != c'} |W_cc'(p)|^2
(per wavelength; wavelengths are independent). The amplitude PSF a is the paraxial Fresnel
integral over the circular pinhole. The wall: 48 pixels over FOV at 2 m, f = 50 mm, 0.2 mm,
450/550/650 nm, 4 x 4 film points a pixel, K = 16 classes on wavecam's class lattice
(core/src/phase_codes.cpp), sources within 14 pixels. Prints the relative noise (RMS over the 16
pixel positions against the class lattice) for cells with no ramp, for sigma = k_c . r with
k_c = u a + v b, and their ratio.
Usage: tests/bench/phase_ramp_model.py [fov-degrees ...]   (about 20 s a field of view)
"""
import sys
import numpy as np

K, WIDTH, F, DEPTH, PINHOLE = 16, 48, 50e-3, 2.0, 0.2e-3
WAVELENGTHS, SUB, REACH = (450e-9, 550e-9, 650e-9), 4, 14
RAMP = (11 / 16, 9 / 16)  # a = (11/16, 0), b = (0, 9/16) cycles per pixel, as phase_codes.cpp


def class_lattice(k):
    """g maximising the shortest same-class distance, and a reduced basis (as PhaseCode)."""
    def shortest(g):
        return min([k * k] + [min(r, k - r) ** 2 + j * j
                              for j in range(1, int(np.sqrt(2 * k)) + 3) for r in [(-g * j) % k]])
    g = max(range(1, k), key=lambda g: (shortest(g), -g))
    a, b = np.array([-g, 1]), np.array([k, 0])
    while True:
        if a @ a > b @ b:
            a, b = b, a
        b = b - round((a @ b) / (a @ a)) * a
        if b @ b >= a @ a:
            return g, a, b


G, B1, B2 = class_lattice(K)


def cell(i, j):
    """The class lattice point nearest pixel (i, j), ties as PhaseCode::cell."""
    basis = np.array([B1, B2]).T
    fu, fv = np.linalg.solve(basis, [i, j])
    best = None
    for cu in (int(np.floor(fu)), int(np.floor(fu)) + 1):
        for cv in (int(np.floor(fv)), int(np.floor(fv)) + 1):
            d = np.subtract((i, j), cu * B1 + cv * B2)
            key = (d @ d, cu, cv)
            best = key if best is None or key < best else best
    return best[1], best[2]


def j0(x):
    t = (np.arange(400) + 0.5) * np.pi / 400
    return np.cos(np.multiply.outer(x, np.sin(t))).mean(axis=-1)


def amplitude_table(wavelength, pitch):
    """a(rho), rho in pixels: integral over the pinhole's radius of J0 times the Fresnel chirp."""
    rho = np.linspace(0, 1.5 * REACH * np.sqrt(2), 1200)
    r = np.linspace(0, PINHOLE / 2, 200)
    chirp = np.exp(1j * np.pi * r ** 2 * (1 / F + 1 / DEPTH) / wavelength) * r
    return rho, np.trapz(j0(2 * np.pi * np.outer(rho * pitch, r) / (wavelength * F)) * chirp, r, axis=1)


def noise(fov, ramp):
    pitch = 2 * F * np.tan(np.radians(fov / 2)) / WIDTH
    tables = [amplitude_table(w, pitch) for w in WAVELENGTHS]
    offsets = (np.arange(SUB) + 0.5) / SUB - 0.5
    variance = []
    for pi in range(4):
        for pj in range(4):  # a 4 x 4 block meets every class once: all positions against the lattice
            film = np.array([(pi + x, pj + y) for x in offsets for y in offsets])
            src = np.array([(i, j) for i in range(pi - REACH, pi + REACH + 1) for j in range(pj - REACH, pj + REACH + 1)])
            m = (src[:, 0] + G * src[:, 1]) % K
            cells = [cell(i, j) for i, j in src]
            index = {c: n for n, c in enumerate(sorted(set(cells)))}
            ci = np.array([index[c] for c in cells])
            uv = np.array(cells)
            r = src - (uv[:, :1] * B1 + uv[:, 1:] * B2)
            sigma = ramp[0] * uv[:, 0] * r[:, 0] + ramp[1] * uv[:, 1] * r[:, 1]
            dist = np.hypot(*(film[:, None, :] - src[None, :, :]).transpose(2, 0, 1))
            var = mean = 0
            for rho, a in tables:
                amp = np.interp(dist, rho, a.real) + 1j * np.interp(dist, rho, a.imag)
                mean += (abs(amp) ** 2).mean(0).sum()
                v = np.zeros((K, len(film), len(index)), complex)
                v[m, :, ci] = (amp * np.exp(2j * np.pi * sigma)).T
                w = np.einsum('mqa,mqb->ab', v, v.conj()) / len(film)
                var += (abs(w) ** 2).sum() - (abs(np.diag(w)) ** 2).sum()
            variance.append(var / mean ** 2)
    return 100 * np.sqrt(np.mean(variance))


if __name__ == '__main__':
    for fov in map(float, sys.argv[1:] or ['5', '10', '20', '40']):
        plain, ramped = noise(fov, (0, 0)), noise(fov, RAMP)
        print(f"{fov:g} deg: cells without a ramp {plain:.2f}%, with the ramp {ramped:.2f}%, ratio {ramped / plain:.2f}")
