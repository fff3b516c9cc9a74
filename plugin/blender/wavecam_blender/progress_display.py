# A running diffraction's progress where Blender shows a job's: the status bar of every window
# and the header of every Image Editor (the render window's included), and the wavecam panel
# (redrawn here). clear() gives the status bar and headers back to Blender.
import bpy

_shown = {"text": None}


def _windows():
    return list(bpy.context.window_manager.windows)


def _set(text):
    for window in _windows():
        with bpy.context.temp_override(window=window, screen=window.screen):
            window.workspace.status_text_set(text)
        for area in window.screen.areas:
            if area.type == 'IMAGE_EDITOR':
                area.header_text_set(text)
            elif area.type == 'PROPERTIES':
                area.tag_redraw()


def show(text):
    if text != _shown["text"]:
        _set(text)
        _shown["text"] = text


def clear():
    if _shown["text"] is not None:
        _set(None)
        _shown["text"] = None


def shown():
    """The progress text now in the status bar, or None (for tests and the panel)."""
    return _shown["text"]
