"""The look of every server the app makes (the lecture app's and a recording's): theme, lights
and the initial camera.  `app.main` and `app.export` both use it; it imports neither."""

from __future__ import annotations

import math

import viser

from app.kit.core.common import CameraView

__all__ = ["BRAND_COLOR", "configure_scene"]

BRAND_COLOR = (200, 110, 0)


def configure_scene(server: viser.ViserServer, view: CameraView) -> None:
    """Theme, lights and the initial camera of a server (the app's, or a recording's)."""
    server.gui.configure_theme(
        show_share_button=False,  # sharing needs an external tunnel: useless offline
        control_width="large",
        brand_color=BRAND_COLOR,
    )
    # Lighting without an HDRI environment map: it looks the same here, and the map's
    # prefiltering costs ~10 s before the first frame under software WebGL (SwiftShader,
    # i.e. a laptop or projector PC without a usable GPU).
    server.scene.configure_environment_map(hdri=None)
    server.scene.configure_default_lights(enabled=True, cast_shadow=False)
    server.scene.add_light_hemisphere(
        "/lights/hemisphere", sky_color=(255, 255, 255), ground_color=(150, 150, 150), intensity=1.5
    )
    server.initial_camera.position = view.position
    server.initial_camera.look_at = view.look_at
    server.initial_camera.up = view.up
    server.initial_camera.fov = math.radians(view.fov_deg)
