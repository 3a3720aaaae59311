"""Every file the app offers a browser is saved at once (`save_download`): the browser's own
download, under the file's whole name, with no toast and link to click first (viser's default,
`save_immediately=False`, shows a toast whose link the user must find)."""

from __future__ import annotations

from typing import Any

__all__ = ["save_download"]


def save_download(client: Any, name: str, data: bytes | str) -> None:
    """Send `data` (bytes, or text sent as UTF-8) to `client`'s browser (a `viser.ClientHandle`),
    which saves it at once as `name`."""
    payload = data.encode("utf-8") if isinstance(data, str) else bytes(data)
    client.send_file_download(name, payload, save_immediately=True)
