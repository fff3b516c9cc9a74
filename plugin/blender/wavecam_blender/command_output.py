# What `wavecam apply` prints on stderr when it is not on a terminal, read for Blender's UI:
#   apply: 48x32 pixels x 8 wavelengths x 64 runs, auto summation (kernel; at 569 nm, kernel: ...) = 4.72e+10 terms, about 1m35s on 2 threads ...
#   apply: 42% after 30s, about 40s left
#   wavecam apply: frame.exr: ... beyond the max-terms limit of 1e+09; lower --runs, ...
# and what a refusal means in the panel's words.
import math
import re
import shlex

_ESTIMATE = re.compile(r"^apply: (?P<job>.*) = (?P<terms>[0-9.e+-]+) terms, about (?P<time>\S+) on ")
_PROGRESS = re.compile(r"^apply: (?P<percent>\d+)% after (?P<elapsed>\S+), (?P<left>.*)$")
_TOO_LARGE = re.compile(r"^(?P<job>.*) = (?P<terms>[0-9.e+-]+) terms, about (?P<time>.+?) at the .* beyond the max-terms limit")
SHARE_TERMS = 1e12  # a cluster task's share: about a quarter of the command's default limit
SOFTWARE_VULKAN = ("llvmpipe", "lavapipe", "swiftshader")


def estimate(line):
    """'about 1m35s' from the command's estimate line, else None."""
    m = _ESTIMATE.match(line)
    return f"about {m.group('time')}" if m else None


def progress(line):
    """(percent, 'about 40s left') from a progress line, else None."""
    m = _PROGRESS.match(line)
    return (int(m.group("percent")), m.group("left")) if m else None


def software_device(line):
    """The device's name where a line names the job's device as a software Vulkan driver
    ("... summation (kernel) on llvmpipe (LLVM 15.0.6, 256 bits) (...) = ..."), else None."""
    m = re.search(r" on ((?:%s)[^(=]*?) \(" % "|".join(SOFTWARE_VULKAN), line, re.IGNORECASE)
    return m.group(1) if m else None


def device_warning(line):
    """What the add-on says when the job runs on software Vulkan, else None."""
    device = software_device(line)
    if not device:
        return None
    return (f"Device GPU is {device}, a software Vulkan driver running on the processor: usually slower than "
            "Device CPU (Auto never takes it)")


def refusal_text(line, farm_command, max_terms):
    """The command's last line as the add-on reports it: a job beyond the panel's Max terms
    points at the panel's settings and at `wavecam farm` with the command to run."""
    line = re.sub(r"^wavecam apply: [^:]*: ", "", line)
    m = _TOO_LARGE.search(line)
    if not m:
        return line
    terms = float(m.group("terms"))
    tasks = max(2, math.ceil(terms / SHARE_TERMS))
    return (f"{m.group('job')} = {terms:.3g} terms, about {m.group('time')} here, beyond Max terms ({max_terms:g}): lower "
            "Runs, Wavelengths or the resolution, or raise Max terms; too large for one machine: share it out on a "
            f"Slurm cluster with: {shlex.join(farm_command + ['--tasks', str(tasks)])}")
