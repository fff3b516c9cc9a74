# Writing the field of view into Blender's own EXR. OpenEXR headers cannot grow in place, so
# the file is copied to a temporary beside it with the attribute added, then renamed over it.
# OpenImageIO 2.4's copy_image decodes and re-encodes the pixels here (measured: as slow as a
# read + write), which is exact for lossless codecs; a file with a lossy codec is left alone.
import os

FOV_ATTRIBUTE = "wavecam.fov"
LOSSY_CODECS = ("dwaa", "dwab", "b44", "b44a", "pxr24")


class TagError(Exception):
    pass


class LossyFile(Exception):
    """The file's codec is lossy: rewriting it would lose more."""


def write_fov(path, fov_degrees):
    """Adds wavecam.fov (float, degrees) to the EXR at `path`. Raises ImportError when
    OpenImageIO's Python bindings are missing, LossyFile for a lossy codec, TagError when the
    file cannot be rewritten."""
    import OpenImageIO as oiio

    source = oiio.ImageInput.open(path)
    if not source:
        raise TagError(f"{path}: {oiio.geterror()}")
    temp = os.path.join(os.path.dirname(path), f".{os.path.basename(path)}.wavecam-tmp{os.getpid()}.exr")
    try:
        if source.seek_subimage(1, 0):  # several parts (stereo views): left alone
            raise TagError(f"{path}: has several parts (stereo?); wavecam tags single-part files only")
        spec = source.spec()
        codec = spec.getattribute("compression") or ""
        if codec.split(":")[0].lower() in LOSSY_CODECS:
            raise LossyFile(f"{path}: {codec} compression is lossy; the file is not rewritten")
        spec.attribute(FOV_ATTRIBUTE, float(fov_degrees))
        out = oiio.ImageOutput.create(temp)
        if not out or not out.open(temp, spec) or not out.copy_image(source) or not out.close():
            raise TagError(f"{path}: cannot write {FOV_ATTRIBUTE}: {out.geterror() if out else oiio.geterror()}")
        source.close()
        os.replace(temp, path)
    finally:
        source.close()
        if os.path.exists(temp):
            os.remove(temp)
