# Add-on preferences: where the wavecam command is (empty: found on PATH).
import shutil

import bpy


class WavecamPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    wavecam_path: bpy.props.StringProperty(
        name="wavecam command", subtype='FILE_PATH', default="",
        description="The wavecam program; empty: the one found on PATH")

    def draw(self, context):
        self.layout.prop(self, "wavecam_path")
        found = wavecam_command(context)
        self.layout.label(text=f"Using: {found}" if found else "wavecam not found: install it or set the path",
                          icon='NONE' if found else 'ERROR')


def wavecam_command(context=None):
    """The wavecam executable to run, or None."""
    context = context or bpy.context
    addon = context.preferences.addons.get(__package__)
    path = bpy.path.abspath(addon.preferences.wavecam_path) if addon and addon.preferences.wavecam_path else ""
    return shutil.which(path) if path else shutil.which("wavecam")


def register():
    bpy.utils.register_class(WavecamPreferences)


def unregister():
    bpy.utils.unregister_class(WavecamPreferences)
