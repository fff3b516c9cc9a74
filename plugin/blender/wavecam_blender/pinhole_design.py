# Rayleigh's optimal pinhole, as wavecam computes its default (core/src/optics/pinhole_design.cpp):
# d = 1.9 sqrt(f lambda) at the design wavelength 550 nm (Rayleigh, Phil. Mag. 31, 1891).
import math

DESIGN_WAVELENGTH_M = 550e-9


def optimal_diameter_mm(film_distance_mm):
    return 1.9 * math.sqrt(film_distance_mm * 1e-3 * DESIGN_WAVELENGTH_M) * 1e3
