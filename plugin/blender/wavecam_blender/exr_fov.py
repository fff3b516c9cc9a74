# Writing the field of view into Blender's own EXR: OpenEXR headers cannot grow in place, so
# the file is copied to a temporary beside it with the attribute added (OpenImageIO's
# copy_image moves the compressed pixels unchanged, no re-encoding), then renamed over it.
import os

FOV_ATTRIBUTE = "wavecam.fov"


class TagError(Exception):
    pass


def write_fov(path, fov_degrees):
    """Adds wavecam.fov (float, degrees) to the EXR at `path`. Raises ImportError when
    OpenImageIO's Python bindings are missing, TagError when the file cannot be rewritten."""
    import OpenImageIO as oiio

    source = oiio.ImageInput.open(path)
    if not source:
        raise TagError(f"{path}: {oiio.geterror()}")
    temp = os.path.join(os.path.dirname(path), f".{os.path.basename(path)}.wavecam-tmp{os.getpid()}.exr")
    try:
        if source.seek_subimage(1, 0):  # several parts (stereo views): left alone
            raise TagError(f"{path}: has several parts (stereo?); wavecam tags single-part files only")
        spec = source.spec()
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
