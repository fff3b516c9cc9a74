# Labels that fit the panel: Blender 3.4 cuts a label at the panel's edge, so a long message is
# broken into rows between words, each measured in the UI's font at the UI's scale.
import blf
import bpy

MARGIN_PX = 48  # a panel's padding on both sides, and a row's own, at UI scale 1
BOX_PX = 14  # a box's padding on both sides
ICON_PX = 24  # the width a row's icon takes


def text_width(text):
    """The width in pixels of `text` as a label draws it."""
    prefs = bpy.context.preferences
    scale = prefs.system.ui_scale
    blf.size(0, prefs.ui_styles[0].widget_label.points * scale)
    return blf.dimensions(0, text)[0]


def available_width(region_width, icon=False, box=False):
    """The width a label's text has in a panel of a region region_width wide."""
    scale = bpy.context.preferences.system.ui_scale
    return region_width - (MARGIN_PX + (ICON_PX if icon else 0) + (BOX_PX if box else 0)) * scale


def rows(text, width_px):
    """`text` broken between words into rows no wider than width_px (a word wider than the
    whole row keeps a row of its own)."""
    out = []
    for word in text.split():
        if out and text_width(out[-1] + " " + word) <= width_px:
            out[-1] += " " + word
        else:
            out.append(word)
    return out


def draw(layout, context, text, icon='NONE', box=False):
    """`text` as a column of labels that fit the region (in a box of its own with box=True);
    the icon on the first row."""
    column = (layout.box() if box else layout).column(align=True)
    width = context.region.width if context.region else 300
    for i, row in enumerate(rows(text, available_width(width, icon != 'NONE', box))):
        column.label(text=row, icon=icon if i == 0 else ('BLANK1' if icon != 'NONE' else 'NONE'))
