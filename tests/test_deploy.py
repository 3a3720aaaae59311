"""deploy/ keeps the tasks (issue 37): the Redis of `deploy/redis-rigid-body-lab.conf` and the one
`deploy/try_here.sh` starts both write an append-only file, the script's in the data folder (not in
its run folder, removed on exit), as `app.cluster.services.start_redis` does when given a folder;
the script's own redis-server command, run twice on one folder, keeps a key across the restart."""

from __future__ import annotations

import re
import secrets
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
CONF = ROOT / "deploy" / "redis-rigid-body-lab.conf"
TRY_HERE = ROOT / "deploy" / "try_here.sh"


def _directives(text: str) -> dict[str, str]:
    """A redis config's directives: name -> value (comments and blank lines left out)."""
    found = {}
    for line in text.splitlines():
        words = line.split("#", 1)[0].split(None, 1)
        if words:
            found[words[0].lower()] = words[1].strip() if len(words) > 1 else ""
    return found


def _redis_command(script: str) -> str:
    """The redis-server command of `script`, its continued lines joined, without what follows
    its `&` (the script's bookkeeping of its children)."""
    match = re.search(r"^redis-server (?:.*\\\n)*.*$", script, flags=re.MULTILINE)
    assert match is not None, "try_here.sh starts no redis-server"
    return match.group(0).replace("\\\n", " ").split("&", 1)[0].strip()


def test_the_deploy_redis_config_writes_an_append_only_file() -> None:
    directives = _directives(CONF.read_text())
    assert directives.get("appendonly") == "yes", directives
    assert directives.get("appendfsync") in ("everysec", "always"), directives


def test_try_here_starts_redis_with_its_append_only_file_in_the_data_folder() -> None:
    script = TRY_HERE.read_text()
    command = _redis_command(script)
    assert "--appendonly yes" in command and "--appendfsync everysec" in command, command
    assert '--dir "$data/redis"' in command, command
    assert 'mkdir -p "$data/redis"' in script
    cleanup = next(line for line in script.splitlines() if line.startswith("cleanup()"))
    assert "$data" not in cleanup, cleanup  # the data folder outlives the script
    assert '--data-dir "$data"' in script  # the workers' data folder is the same


def test_try_heres_redis_keeps_a_key_across_a_restart(tmp_path: Path) -> None:
    from app.cluster import services

    try:
        services.require("redis-server")
        import redis
    except (services.MissingProgram, ImportError) as error:
        pytest.skip(str(error))
    command = _redis_command(TRY_HERE.read_text())
    password = secrets.token_urlsafe(12)

    def start() -> tuple[subprocess.Popen[bytes], redis.Redis]:
        port = services.free_port()
        shell = f"rport={port}; password={password}; data={tmp_path}; mkdir -p \"$data/redis\"; exec {command}"
        process = subprocess.Popen(["bash", "-c", shell])
        services.wait_for_port(port, "127.0.0.1", process=process)
        return process, redis.Redis(port=port, password=password, decode_responses=True)

    process, client = start()
    try:
        client.set("rigid-body-lab:task:TEST", "kept")
    finally:
        client.close()
        services.stop_process(process)
    assert any((tmp_path / "redis").rglob("*.aof")), list((tmp_path / "redis").rglob("*"))
    process, client = start()
    try:
        assert client.get("rigid-body-lab:task:TEST") == "kept"
    finally:
        client.close()
        services.stop_process(process)
