"""LCM log files and our LCM message types, without the python `lcm` module.

Log format (what lcm-logger writes; apps/common/lcm_log_reader.hpp), every
field big-endian, events back to back:
    uint32 sync word 0xEDA1DA01, int64 event number, int64 utime,
    int32 channel length, int32 data length, channel bytes, data bytes.

The message classes are generated at run time by `lcm-gen --python` from
lcmtypes/*.lcm into a temporary directory (never committed); the generated
code needs only `struct`.
"""

import atexit
import importlib
import os
import shutil
import struct
import subprocess
import sys
import tempfile

SYNC = 0xEDA1DA01
_HEADER = struct.Struct(">Iqqii")


class LogError(Exception):
    pass


def read_events(path):
    """Yields (event_number, utime, channel, data) for every event of the log.

    Strict: a damaged or cut log is an error (export must not drop data
    silently); sf-mapper's own reader is the one that reads past damage."""
    with open(path, "rb") as f:
        blob = f.read()
    off, n = 0, len(blob)
    while off < n:
        if n - off < _HEADER.size:
            raise LogError(f"{path}: cut short inside the event header at byte {off}")
        sync, ev, utime, clen, dlen = _HEADER.unpack_from(blob, off)
        if sync != SYNC:
            raise LogError(f"{path}: no sync word at byte {off} (damaged log)")
        if clen <= 0 or dlen < 0 or off + _HEADER.size + clen + dlen > n:
            raise LogError(f"{path}: event at byte {off} has bad lengths or is cut short (damaged log)")
        p = off + _HEADER.size
        channel = blob[p:p + clen].decode("utf-8", "replace")
        data = blob[p + clen:p + clen + dlen]
        yield ev, utime, channel, data
        off = p + clen + dlen


def with_latest_nav(path, channel):
    """Yields (nav, data) for every event on `channel` that comes after a NAV message: nav is the
    latest NAV decoded (types().nav_state_t), data the event's raw bytes (decode what you use)."""
    nav_t = types().nav_state_t
    nav = None
    for _, _, ch, data in read_events(path):
        if ch == "NAV":
            nav = nav_t.decode(data)
        elif ch == channel and nav is not None:
            yield nav, data


class LogWriter:
    """Writes an LCM log to PATH atomically: to a temporary file beside it,
    renamed over PATH by commit(); abort() (or an exception inside `with`)
    removes the temporary, so nothing half-written is left."""

    def __init__(self, path):
        self.path = path
        d = os.path.dirname(os.path.abspath(path))
        fd, self.tmp = tempfile.mkstemp(prefix=os.path.basename(path) + ".", suffix=".tmp", dir=d)
        self.f = os.fdopen(fd, "wb")
        self.events = 0

    def write(self, utime, channel, data):
        ch = channel.encode("utf-8")
        self.f.write(_HEADER.pack(SYNC, self.events, utime, len(ch), len(data)))
        self.f.write(ch)
        self.f.write(data)
        self.events += 1

    def commit(self):
        self.f.flush()
        os.fsync(self.f.fileno())
        self.f.close()
        os.replace(self.tmp, self.path)

    def abort(self):
        if not self.f.closed:
            self.f.close()
        if os.path.exists(self.tmp):
            os.remove(self.tmp)

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb):
        if exc_type is not None:
            self.abort()
        return False


_types = None


def types():
    """The generated message classes: a namespace with fls_image_t, ps_ping_t, nav_state_t."""
    global _types
    if _types is not None:
        return _types
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    lcmdir = os.path.join(root, "lcmtypes")
    files = sorted(os.path.join(lcmdir, f) for f in os.listdir(lcmdir) if f.endswith(".lcm"))
    lcm_gen = shutil.which("lcm-gen")
    if not lcm_gen:
        raise LogError("lcm-gen not found (Debian package liblcm-bin; tools/install-deps installs it)")
    out = tempfile.mkdtemp(prefix="sfbag-lcmgen-")
    atexit.register(shutil.rmtree, out, True)
    subprocess.run([lcm_gen, "--python", "--ppath", out] + files, check=True, stdout=subprocess.DEVNULL)
    sys.path.insert(0, out)
    try:
        mods = {n: importlib.import_module("sonarfusion." + n) for n in ("fls_image_t", "ps_ping_t", "nav_state_t")}
    finally:
        sys.path.remove(out)

    class _T:
        pass

    _types = _T()
    for n, m in mods.items():
        setattr(_types, n, getattr(m, n))
    return _types


def decode(cls, data, what):
    """cls.decode(data), with a bounds and trailing-bytes check the generated code lacks."""
    try:
        msg = cls.decode(data)
    except (ValueError, struct.error) as e:
        raise LogError(f"{what}: cannot decode as {cls.__name__} ({e or 'wrong fingerprint'})") from None
    if len(msg.encode()) != len(data):
        raise LogError(f"{what}: {cls.__name__} with trailing or missing bytes")
    return msg
