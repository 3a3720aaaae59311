"""Per-preset probe (after /work/prompts/probe.py): kB/s per playing browser, msgs/frame,
and each message kind's marginal bytes.  Run from the worktree root:
    python scripts/probe_presets.py "Euler angles" [-v]   (-v: each message kind's marginal kB/s)"""
import sys, collections, os
ROOT = os.getcwd(); sys.path.insert(0, ROOT); sys.path.insert(0, ROOT + "/tests")
from viser.infra import _async_message_buffer as amb
from conftest import RawClient
from app.main import create_server
log = []
orig = amb.AsyncMessageBuffer.push
def push(self, m):
    log.append(m); return orig(self, m)
amb.AsyncMessageBuffer.push = push
import msgspec, zstandard
z = zstandard.ZstdCompressor(level=1)
def size(msgs):
    if not msgs: return 0
    bufs=[]
    ser = tuple(m.as_serializable_dict(bufs) for m in msgs)
    inner = msgspec.msgpack.encode({"messages": ser, "timestampSec": 1.0, "binaryBufferLengths": tuple(b.nbytes for b in bufs)})
    return 16 + len(z.compress(inner)) + sum(b.nbytes for b in bufs)
def key(m):
    k = type(m).__name__.replace("Message","") + " " + str(getattr(m, "name", getattr(m, "uuid", "")))[:44]
    if hasattr(m, "updates"): k += " " + ",".join(m.updates.keys())
    return k
verbose = "-v" in sys.argv
names = [a for a in sys.argv[1:] if a != "-v"]
app = create_server("127.0.0.1", 0, verbose=False, start_loop=False)
c = RawClient(app.port)
s = next(iter(app.wait_for_sessions(1).values()))
N = 240
for name in names:
    s.select_scene(name)
    scene = s.view.__class__ if hasattr(s, "view") else None
    from app.scenes import SCENES
    cls = SCENES[name]
    for preset in cls.presets():
        s.apply_preset(preset.name)
        s.play()
        for _ in range(60): s.tick(1/60)
        log.clear(); per=[]
        for _ in range(N):
            n0=len(log); s.tick(1/60); per.append(log[n0:])
        total = sum(size(fr) for fr in per)
        print(f"== {name} / {preset.name}: {sum(len(f) for f in per)/N:.2f} msgs/frame, {total/N*60/1e3:.2f} kB/s, {sum(1 for f in per if f)/N*60:.0f} windows/s")
        if verbose:
            counts=collections.Counter(); marg=collections.Counter()
            for fr in per:
                full=size(fr)
                for k in set(key(m) for m in fr):
                    marg[k]+= full-size([m for m in fr if key(m)!=k])
                for m in fr: counts[key(m)]+=1
            for k,v in marg.most_common(30): print(f"   {counts[k]/N:5.2f}/fr {v/N*60/1e3:6.2f} kB/s  {k}")
        s.pause()
c.close(); app.stop()
