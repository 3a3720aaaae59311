#!/usr/bin/env bash
# Try deploy/ on one machine, as if on several: Redis with a password, two workers started as the
# service file starts them (the environment file's variables, --host/--port/--worker-id), and
# nginx with deploy/nginx-rigid-body-lab.conf (the workers' addresses and the port replaced).
# Redis writes its append-only file in the data folder's redis/ (as deploy/redis-rigid-body-lab.conf and
# the app's own redis-server do): the tasks made here and their submissions survive a restart.
#   deploy/try_here.sh [PORT]        (Ctrl-C stops everything; the app's venv active, or PYTHON=...)
#   RBL_DATA_DIR=FOLDER deploy/try_here.sh   (the data folder; default the app's, as --data-dir's)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"; root="$(dirname "$here")"
port="${1:-8090}"; run="$(mktemp -d)"; python="${PYTHON:-python}"
data="${RBL_DATA_DIR:-${XDG_DATA_HOME:-$HOME/.local/share}/rigid-body-lab}"  # app.userdata's, on Linux
mkdir -p "$data/redis"
free() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
rport=$(free); w1=$(free); w2=$(free)
password=$(python3 -c 'import secrets; print(secrets.token_urlsafe(24))')
pids=()
cleanup() { kill "${pids[@]}" 2>/dev/null || true; wait 2>/dev/null || true; rm -rf "$run"; }
trap cleanup EXIT INT TERM
redis-server --port "$rport" --bind 127.0.0.1 --requirepass "$password" --save '' --appendonly yes \
    --appendfsync everysec --dir "$data/redis" --loglevel warning >/dev/null & pids+=($!)
export RBL_REDIS_URL="redis://:$password@127.0.0.1:$rport/0"
export RBL_PRESENTER_CODE="$(python3 -c 'import secrets; n=secrets.randbelow(10**8); print(f"{n:08d}"[:4], f"{n:08d}"[4:])')"
for w in "$w1" "$w2"; do
    (cd "$root" && exec "$python" -m app --host 127.0.0.1 --port "$w" --data-dir "$data" --worker-id "$(hostname)-$w" >"$run/w$w.log" 2>&1) &
    pids+=($!)
done
sed -e "/^    server 10\./d" -e "s|^    zone rigid_body_lab 64k;.*|&\n    server 127.0.0.1:$w1;\n    server 127.0.0.1:$w2;|" \
    -e "s|listen 80;|listen 127.0.0.1:$port;|" "$here/nginx-rigid-body-lab.conf" > "$run/site.conf"
cat > "$run/nginx.conf" <<CONF
daemon off; worker_processes 1; pid $run/nginx.pid; error_log $run/nginx-error.log warn;
events { worker_connections 4096; }
http { client_body_temp_path $run/cb; proxy_temp_path $run/px; fastcgi_temp_path $run/fc;
       uwsgi_temp_path $run/uw; scgi_temp_path $run/sc; include $run/site.conf; }
CONF
for w in "$w1" "$w2"; do
    for _ in $(seq 600); do
        grep -q "worker .* on http" "$run/w$w.log" 2>/dev/null && break
        grep -q "Error" "$run/w$w.log" 2>/dev/null && { cat "$run/w$w.log"; exit 1; }
        sleep 0.2
    done
done
/usr/sbin/nginx -p "$run" -c "$run/nginx.conf" -e "$run/nginx-error.log" & pids+=($!)
echo "open http://127.0.0.1:$port in a browser; presenter code: $RBL_PRESENTER_CODE (workers on $w1 and $w2;" \
     "tasks kept in $data/redis)"
wait
