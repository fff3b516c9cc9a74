# A running diffraction's progress where Blender shows its own jobs': a bar with a cancel cross
# in the status bar of every window, drawn into Blender's own status bar (its width fixed, so
# that nothing beside it moves as the text changes; a text too long for it is cut by Blender),
# and the wavecam panel (redrawn here). The Image Editors' headers are left to Blender.
import bpy

_shown = {"text": None, "bar": None}
BAR_UNITS = 14  # the bar's width in UI units, whatever it says


def _percent(self):
    return _shown["bar"][0] if _shown["bar"] else 0.0


def bar_text():
    """What the bar says beside its percentage: the frame, and the time left once known."""
    return _shown["bar"][1] if _shown["bar"] else ""


def draw_bar(layout, context):
    """The bar and its cancel cross (the status bar, the panel)."""
    row = layout.row(align=True)
    bar = row.row(align=True)
    bar.ui_units_x = BAR_UNITS
    bar.prop(context.window_manager, "wavecam_progress", text=bar_text(), slider=True)
    row.operator("wavecam.cancel", text="", icon='X')


def _draw_status(self, context):
    if _shown["text"] is not None:
        draw_bar(self.layout, context)


def _redraw():
    for window in bpy.context.window_manager.windows:
        # (setting no text redraws the status bar as Blender draws it, the bar included)
        with bpy.context.temp_override(window=window, screen=window.screen):
            window.workspace.status_text_set(None)
        for area in window.screen.areas:
            if area.type == 'PROPERTIES':
                area.tag_redraw()


def show(text, percent=0.0, short="wavecam"):
    """`text`: the whole line (the panel); `percent` and `short` ("wavecam: frame 1, 40s left"): the bar."""
    bar = (float(percent), short)
    if text != _shown["text"] or bar != _shown["bar"]:
        _shown["text"], _shown["bar"] = text, bar
        _redraw()


def clear():
    if _shown["text"] is not None:
        _shown["text"], _shown["bar"] = None, None
        _redraw()


def shown():
    """The progress text now shown, or None (for tests and the panel)."""
    return _shown["text"]


def register():
    bpy.types.WindowManager.wavecam_progress = bpy.props.FloatProperty(
        name="wavecam", subtype='PERCENTAGE', min=0.0, max=100.0, precision=0, get=_percent,
        description="How much of the frame wavecam has diffracted; the cross beside it cancels")
    bpy.types.STATUSBAR_HT_header.append(_draw_status)


def unregister():
    bpy.types.STATUSBAR_HT_header.remove(_draw_status)
    del bpy.types.WindowManager.wavecam_progress
