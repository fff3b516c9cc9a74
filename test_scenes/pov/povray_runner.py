"""Running POV-Ray on a scene or on a wrapper that #includes it, and reading what it wrote."""
import glob
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
# Every parse prints what POV-Ray itself will render: the image's size (the user's ini or options
# may set it) and the clock (animation), so that what can be refused is refused after this run.
SEEN_SDL = ('#debug concat("wavecam-seen ", str(image_width, 0, 0), " ", str(image_height, 0, 0), " ", '
            'str(clock, 0, 9), " ", str(frame_number, 0, 0), "\\n")\n')


def quoted(path):
    """A path as one POV-Ray option value: POV-Ray splits an option at spaces unless the value is
    quoted inside the argument (+I"/a b/c.pov"; docs/platform_notes.md)."""
    if '"' in path:
        raise Refusal(f"{path}: POV-Ray cannot be given a path containing a double quote")
    return f'"{path}"' if any(c.isspace() for c in path) else path


class Povray:
    def __init__(self, scene, tmp, size, user_options=(), frame_options=()):
        self.scene, self.tmp, self.size, self.runs = scene, tmp, size, 0
        self.user_options = list(user_options)    # ini files, Declare=, +Q...: every run
        self.frame_options = list(frame_options)  # +KFI +KFF +SF +EF: this frame only
        self.probe_scene = scene                  # what a parse #includes (render_pov: a copy
        self.seen = None                          # with top-level #local made #declare)

    def parse(self, sdl, what):
        """Parse the scene and sdl without rendering (no radiosity pretrace, no pixels):
        an #error at the end stops POV-Ray once everything before it has parsed. Records the
        image size, clock and frame POV-Ray parsed with in self.seen."""
        try:
            self.run(sdl + SEEN_SDL + f'#error "{PARSED}"\n', ["-F"], what, include=self.probe_scene)
        except PovrayFailed as e:
            if PARSED not in e.log:
                raise
            seen = [l.split()[1:] for l in e.log.splitlines() if l.startswith("wavecam-seen ")]
            if seen:
                w, h, clock, frame = seen[-1]
                self.seen = (int(w), int(h), float(clock), int(frame))
            return e.log
        raise PovrayFailed(f"POV-Ray did not stop at the end of the {what}", "", True)

    def run(self, sdl, options, what, include=None, defaults=()):
        """Render the scene itself (sdl None) or a wrapper that #includes it (or `include`) and
        adds sdl; returns (log, exr path or None). `defaults` go before the user's options (which
        may override them), `options` after (they win)."""
        self.runs += 1
        print(f"render_pov.sh: POV-Ray run {self.runs}: {what}", file=sys.stderr, flush=True)  # progress
        wrapper = self.scene
        included = include or self.scene
        if sdl is not None:
            wrapper = os.path.join(self.tmp, f"pass{self.runs}.pov")
            with open(wrapper, "w") as f:
                f.write(f'#include "{included}"\n{sdl}')
        # An animated run appends the frame number to the name (pass3_02.exr): found by prefix.
        prefix = os.path.join(self.tmp, f"pass{self.runs}_")
        out = prefix + ".exr"
        parse_only = "-F" in options
        size = [f"+W{self.size[0]}", f"+H{self.size[1]}"] if self.size[0] else []
        cmd = ["povray", *defaults, *self.user_options, *self.frame_options, "-D", "-P", "-UA", "-V",
               f"+I{quoted(wrapper)}",
               f"+L{quoted(os.path.dirname(self.scene))}", *size, *options]
        cmd += ["+FE", f"+O{out}"] if not parse_only else []
        proc = subprocess.run(cmd, cwd=os.path.dirname(self.scene), capture_output=True, text=True,
                              errors="replace", stdin=subprocess.DEVNULL)
        log = proc.stdout + proc.stderr
        written = sorted(glob.glob(glob.escape(prefix) + "*.exr"))
        if proc.returncode != 0 or (not parse_only and not written):
            message = povray_message(log)
            if included != self.scene:  # the #local copy: name the user's file
                message = message.replace(included, self.scene)
            raise PovrayFailed(f"POV-Ray failed on the {what}:\n{message}", log,
                               wrapper != self.scene and os.path.basename(wrapper) in message)
        return log, (written[-1] if not parse_only else None)


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
