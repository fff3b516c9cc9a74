"""Running POV-Ray on a scene or on a wrapper that #includes it, and reading what it wrote."""
import os
import re
import subprocess
import sys

import numpy as np
import OpenImageIO as oiio


class Refusal(Exception):
    pass


class PovrayFailed(Refusal):
    def __init__(self, message, log, in_wrapper):
        super().__init__(message)
        self.log = log
        self.in_wrapper = in_wrapper  # the error is in our added SDL, not in the scene


PARSED = "wavecam: parsed"


class Povray:
    def __init__(self, scene, tmp, size):
        self.scene, self.tmp, self.size, self.runs = scene, tmp, size, 0

    def parse(self, sdl, what):
        """Parse the scene and sdl without rendering (no radiosity pretrace, no pixels):
        an #error at the end stops POV-Ray once everything before it has parsed."""
        try:
            self.run(sdl + f'#error "{PARSED}"\n', ["-F"], what)
        except PovrayFailed as e:
            if PARSED not in e.log:
                raise
            return e.log
        raise PovrayFailed(f"POV-Ray did not stop at the end of the {what}", "", True)

    def run(self, sdl, options, what):
        """Render the scene itself (sdl None) or a wrapper that #includes it and adds sdl;
        returns (log, exr path or None)."""
        self.runs += 1
        print(f"render_pov.sh: POV-Ray run {self.runs}: {what}", file=sys.stderr, flush=True)  # progress
        wrapper = self.scene
        if sdl is not None:
            wrapper = os.path.join(self.tmp, f"pass{self.runs}.pov")
            with open(wrapper, "w") as f:
                f.write(f'#include "{self.scene}"\n{sdl}')
        out = os.path.join(self.tmp, f"pass{self.runs}.exr")
        size = [f"+W{self.size[0]}", f"+H{self.size[1]}"] if self.size[0] else []
        cmd = ["povray", "-D", "-V", f"+I{wrapper}", f"+L{os.path.dirname(self.scene)}", *size, *options]
        cmd += ["+FE", f"+O{out}"] if "-F" not in options else []
        proc = subprocess.run(cmd, cwd=os.path.dirname(self.scene), capture_output=True, text=True,
                              errors="replace")
        log = proc.stdout + proc.stderr
        if proc.returncode != 0 or (out and "-F" not in options and not os.path.exists(out)):
            message = povray_message(log)
            raise PovrayFailed(f"POV-Ray failed on the {what}:\n{message}", log,
                               wrapper != self.scene and os.path.basename(wrapper) in message)
        return log, (out if "-F" not in options else None)


def povray_message(log):
    """POV-Ray's own error lines (the file/line and the message)."""
    lines = log.splitlines()
    keep = [i for i, l in enumerate(lines) if re.search(r"error", l, re.I) and "Error Stream" not in l]
    if not keep:
        return "\n".join(lines[-8:])
    picked = []
    for i in keep:
        picked += lines[max(0, i - 1):i + 3]
    return "\n".join(dict.fromkeys(picked))


def read(path):
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        raise Refusal(f"cannot read POV-Ray's output {path}: {buf.geterror()}")
    return buf.get_pixels(oiio.FLOAT)[..., :3].astype(np.float64)
