#!/usr/bin/python3
"""A star field: single lit pixels on black sky, every 64 pixels over a square frame, written as
a radiance + depth OpenEXR (R, G, B, Z; Z infinite: every star is a plane wave) with the frame's
field of view in `wavecam.fov`. Each star's image through wavecam is then its PSF at that field.

Usage: star_field.py OUT.exr [--size 512] [--fov 60]"""
import argparse

import numpy as np
import OpenImageIO as oiio

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("out")
parser.add_argument("--size", type=int, default=512)
parser.add_argument("--fov", type=float, default=60.0, help="horizontal field of view, degrees")
args = parser.parse_args()

n = args.size
pixels = np.zeros((n, n, 4), dtype=np.float32)
pixels[:, :, 3] = np.inf
for j in range(n // 16, n, n // 8):
    for i in range(n // 16, n, n // 8):
        pixels[j, i, :3] = 1.0
# and one on the axis
pixels[n // 2, n // 2, :3] = 1.0
spec = oiio.ImageSpec(n, n, 4, "float")
spec.channelnames = ("R", "G", "B", "Z")
spec.attribute("wavecam.fov", float(args.fov))
out = oiio.ImageOutput.create(args.out)
if not out or not out.open(args.out, spec) or not out.write_image(pixels) or not out.close():
    raise SystemExit(f"star_field.py: cannot write {args.out}: {oiio.geterror()}")
