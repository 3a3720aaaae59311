"""Debian's Chromium for headless WebGL screenshots and browser tests (flags of docs/VISER.md).

Software WebGL through SwiftShader; `--run-all-compositor-stages-before-draw` makes complete
frames reliable; the background-networking flags keep it off the closed network.
"""

import os

CHROMIUM = os.environ.get("CHROMIUM", "/usr/lib/chromium/chromium")
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--enable-unsafe-swiftshader",
    "--use-angle=swiftshader",
    "--run-all-compositor-stages-before-draw",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
INSTALL_HINT = "install it with `apt-get install chromium` (and `pip install playwright`)"
