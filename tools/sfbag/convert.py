"""sf-bag export (LCM log -> ROS 2 bag) and import (ROS 2 bag -> LCM log).
The mapping, frames, element order and dtype scaling are in docs/ros2.md."""

import math
import os
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

from . import frames, lcmlog, rosmsgs


class BagError(Exception):
    pass


DEFAULT_TOPICS = {"fls": "/sonarfusion/fls", "ps": "/sonarfusion/ps", "nav": "/sonarfusion/odom",
                  "nav_ned": "/sonarfusion/nav_ned"}
RANK = {"nav": 0, "ps": 1, "fls": 2}  # order of same-stamp events, as sf-sim writes them


def stamp_of(ts_types, utime):
    Time = ts_types["builtin_interfaces/msg/Time"]
    return Time(sec=int(utime // 1_000_000), nanosec=int(utime % 1_000_000) * 1000)


def utime_of(stamp):
    return int(stamp.sec) * 1_000_000 + int(stamp.nanosec) // 1000


# ----------------------------------------------------------------------------- export

def fls_to_ros(T, m, what):
    B, R = m.num_beams, m.num_ranges
    if B <= 0 or R <= 0 or m.data_size != B * R or len(m.data) != B * R:
        raise BagError(f"{what}: FLS frame of {B} beams x {R} ranges holds {m.data_size} bytes")
    img = np.frombuffer(m.data, dtype=np.uint8).reshape(R, B)
    # Ours: row 0 the farthest range. ROS drivers: ranges ascending. Flip the rows.
    img = img[::-1]
    ranges = np.asarray(m.row_range, dtype=np.float32)[::-1].copy()
    V = T["geometry_msgs/msg/Vector3"]
    # Sonar frame: Z forward, X up, Y starboard; our bearing is + to starboard.
    dirs = [V(x=0.0, y=math.sin(b), z=math.cos(b)) for b in m.beam_bearing]
    width = np.float32(m.elevation_max) - np.float32(m.elevation_min)
    return T[rosmsgs.PSI](
        header=T["std_msgs/msg/Header"](stamp=stamp_of(T, m.utime), frame_id=m.sensor_name),
        ping_info=T[rosmsgs.PING](frequency=m.frequency_hz, sound_speed=m.sound_speed,
                                  tx_beamwidths=np.full(B, width, dtype=np.float32),
                                  rx_beamwidths=np.zeros(0, dtype=np.float32)),
        beam_directions=dirs, ranges=ranges,
        image=T[rosmsgs.DATA](is_bigendian=False, dtype=0, beam_count=B,
                              data=np.ascontiguousarray(img).reshape(-1)))


def ps_to_ros(T, m, what):
    n = m.num_bins
    if n <= 0 or len(m.intensity) != n:
        raise BagError(f"{what}: PS ping of {n} bins holds {len(m.intensity)} bytes")
    # Bin centres from range_min to range_max; the end points exactly.
    r = np.array([m.range_min + (m.range_max - m.range_min) * i / (n - 1) if n > 1 else m.range_min
                  for i in range(n)], dtype=np.float32)
    r[0], r[-1] = m.range_min, m.range_max
    h = m.head_angle  # + looks down: direction (forward cos h, down sin h) -> X up = -sin h
    V = T["geometry_msgs/msg/Vector3"]
    return T[rosmsgs.PSI](
        header=T["std_msgs/msg/Header"](stamp=stamp_of(T, m.utime), frame_id=m.sensor_name),
        ping_info=T[rosmsgs.PING](frequency=0.0, sound_speed=0.0, tx_beamwidths=np.zeros(0, dtype=np.float32),
                                  rx_beamwidths=np.array([np.float32(m.fan_max) - np.float32(m.fan_min)],
                                                         dtype=np.float32)),
        beam_directions=[V(x=-math.sin(h), y=0.0, z=math.cos(h))], ranges=r,
        image=T[rosmsgs.DATA](is_bigendian=False, dtype=0, beam_count=1,
                              data=np.frombuffer(m.intensity, dtype=np.uint8).copy()))


def nav_to_ros(T, m):
    p, q, v = frames.ned_frd_to_enu_flu(m.position_ned, m.rpy, m.velocity_ned)
    G = lambda n: T["geometry_msgs/msg/" + n]  # noqa: E731
    return T[rosmsgs.ODOM](
        header=T["std_msgs/msg/Header"](stamp=stamp_of(T, m.utime), frame_id="map"),
        child_frame_id="base_link",
        pose=G("PoseWithCovariance")(pose=G("Pose")(position=G("Point")(x=p[0], y=p[1], z=p[2]),
                                                    orientation=G("Quaternion")(x=q[0], y=q[1], z=q[2], w=q[3])),
                                     covariance=np.zeros(36, dtype=np.float64)),
        twist=G("TwistWithCovariance")(twist=G("Twist")(linear=G("Vector3")(x=v[0], y=v[1], z=v[2]),
                                                        angular=G("Vector3")(x=0.0, y=0.0, z=0.0)),
                                       covariance=np.zeros(36, dtype=np.float64)))


def nav_state_to_ros(T, m):
    return T[rosmsgs.NAVSTATE](
        header=T["std_msgs/msg/Header"](stamp=stamp_of(T, m.utime), frame_id="ned"),
        position_ned=np.array(m.position_ned, dtype=np.float64), rpy=np.array(m.rpy, dtype=np.float64),
        velocity_ned=np.array(m.velocity_ned, dtype=np.float64), altitude=float(m.altitude))


def export(log, out_bag, storage="sqlite3", channels=None, topics=None, quiet=False):
    from rosbags.rosbag2 import StoragePlugin, Writer

    channels = channels or {"fls": "FLS", "ps": "PS", "nav": "NAV"}
    topics = topics or DEFAULT_TOPICS
    by_channel = {ch: kind for kind, ch in channels.items()}
    if os.path.exists(out_bag):
        raise BagError(f"{out_bag} exists already, not overwriting")
    plugin = {"sqlite3": StoragePlugin.SQLITE3, "mcap": StoragePlugin.MCAP}[storage]
    L = lcmlog.types()
    ts = rosmsgs.typestore()
    T = ts.types
    # Written inside a temporary folder beside OUT_BAG (so the storage file
    # already has its final name), moved into place at the end.
    parent = tempfile.mkdtemp(prefix=".sf-bag-", dir=os.path.dirname(os.path.abspath(out_bag)))
    tmp = os.path.join(parent, os.path.basename(os.path.abspath(out_bag)))
    counts = {k: 0 for k in channels}
    skipped = {}
    try:
        with Writer(tmp, version=9, storage_plugin=plugin) as w:
            conns = {}
            for ev, utime, channel, data in lcmlog.read_events(log):
                kind = by_channel.get(channel)
                if kind is None:
                    skipped[channel] = skipped.get(channel, 0) + 1
                    continue
                what = f"{log}: event {ev} on {channel}"
                if kind == "fls":
                    msg, typ = fls_to_ros(T, lcmlog.decode(L.fls_image_t, data, what), what), rosmsgs.PSI
                elif kind == "ps":
                    msg, typ = ps_to_ros(T, lcmlog.decode(L.ps_ping_t, data, what), what), rosmsgs.PSI
                else:
                    nav = lcmlog.decode(L.nav_state_t, data, what)
                    msg, typ = nav_to_ros(T, nav), rosmsgs.ODOM
                    if topics.get("nav_ned"):
                        if "nav_ned" not in conns:
                            conns["nav_ned"] = w.add_connection(topics["nav_ned"], rosmsgs.NAVSTATE, typestore=ts)
                        w.write(conns["nav_ned"], utime * 1000,
                                ts.serialize_cdr(nav_state_to_ros(T, nav), rosmsgs.NAVSTATE))
                if kind not in conns:
                    conns[kind] = w.add_connection(topics[kind], typ, typestore=ts)
                w.write(conns[kind], utime * 1000, ts.serialize_cdr(msg, typ))
                counts[kind] += 1
        os.rename(tmp, out_bag)
    finally:
        shutil.rmtree(parent, ignore_errors=True)
    if not quiet:
        print(f"sf-bag export: {out_bag} ({storage}): " +
              ", ".join(f"{topics[k]} {counts[k]}" for k in ("nav", "fls", "ps")) +
              "".join(f"; skipped channel {c}: {n}" for c, n in sorted(skipped.items())))
    return counts


# ----------------------------------------------------------------------------- import

def to_uint8(arr, dtype, float_full_scale=1.0):
    """The documented scaling of any SonarImageData dtype onto 0..255."""
    code, bits, signed, isfloat = rosmsgs.DTYPES[dtype]
    if dtype == 0:
        return arr.astype(np.uint8, copy=False)
    if isfloat:
        a = np.nan_to_num(arr.astype(np.float64), nan=0.0, posinf=float_full_scale, neginf=0.0)
        return np.clip(np.rint(a * (255.0 / float_full_scale)), 0, 255).astype(np.uint8)
    if signed:  # negative -> 0; the positive half's top 8 bits
        a = np.maximum(arr, 0).astype(np.uint64)
        return (a << 1).astype(np.uint8) if bits == 8 else (a >> (bits - 9)).astype(np.uint8)
    return (arr.astype(np.uint64) >> (bits - 8)).astype(np.uint8)


def load_sensor_config(path):
    """What a ProjectedSonarImage does not carry (tilt, mounting, PS fan, a
    default aperture), from the mapper config (or a scenario: same keys)."""
    from ruamel.yaml import YAML

    with open(path) as f:
        root = YAML(typ="safe").load(f) or {}

    def sensor(name, keys):
        node = root.get(name) or {}
        out = {}
        for k in keys:
            if k not in node:
                raise BagError(f"{path}: {name}.{k} missing (import takes it from the config)")
            out[k] = np.float32(math.radians(float(node[k])))
        mnt = node.get("mount") or {}
        out["mount_xyz"] = [float(np.float32(mnt.get(k, 0.0))) for k in ("x", "y", "z")]
        out["mount_roll_yaw"] = [float(np.float32(math.radians(float(mnt.get(k, 0.0))))) for k in ("roll_deg", "yaw_deg")]
        return out

    return {"fls": sensor("fls", ("tilt_deg", "elevation_min_deg", "elevation_max_deg")),
            "ps": sensor("ps", ("tilt_deg", "fan_min_deg", "fan_max_deg"))}


def _image(msg, topic, idx):
    """(uint8 image as ranges x beams in the bag's order, ranges, directions)."""
    img = msg.image
    B, R = int(img.beam_count), len(msg.ranges)
    where = f"{topic} message {idx}"
    if int(img.dtype) not in rosmsgs.DTYPES:
        raise BagError(f"{where}: unknown image dtype {img.dtype}")
    if B <= 0 or R <= 0:
        raise BagError(f"{where}: empty image ({B} beams, {R} ranges)")
    if len(msg.beam_directions) != B:
        raise BagError(f"{where}: {len(msg.beam_directions)} beam_directions but beam_count {B}")
    code = rosmsgs.DTYPES[int(img.dtype)][0]
    size = np.dtype(code).itemsize
    if len(img.data) != B * R * size:
        raise BagError(f"{where}: image.data holds {len(img.data)} bytes, but beam_count {B} x {R} ranges x "
                       f"{size} byte(s) = {B * R * size}")
    arr = np.frombuffer(np.asarray(img.data, dtype=np.uint8).tobytes(),
                        dtype=np.dtype(code).newbyteorder(">" if img.is_bigendian else "<"))
    # Element order: range-major, beams contiguous (docs/ros2.md, with its sources).
    arr = arr.reshape(R, B)
    ranges = np.asarray(msg.ranges, dtype=np.float32)
    dirs = np.array([[d.x, d.y, d.z] for d in msg.beam_directions], dtype=np.float64)
    if not (np.all(np.isfinite(ranges)) and np.all(np.isfinite(dirs))):
        raise BagError(f"{where}: non-finite ranges or beam directions")
    return arr, ranges, dirs


def ros_to_fls(L, msg, topic, idx, cfg, fscale):
    arr, ranges, dirs = _image(msg, topic, idx)
    u8 = to_uint8(arr, int(msg.image.dtype), fscale)
    bearing = np.arctan2(dirs[:, 1], dirs[:, 2])  # + to starboard (Y)
    cols = np.argsort(bearing, kind="stable")       # column 0 the port-most beam
    rows = np.argsort(-ranges, kind="stable")        # row 0 the farthest range
    m = L.fls_image_t()
    m.utime = utime_of(msg.header.stamp)
    m.sensor_name = msg.header.frame_id
    m.sound_speed = float(msg.ping_info.sound_speed)
    m.frequency_hz = float(msg.ping_info.frequency)
    m.mount_xyz = cfg["mount_xyz"]
    m.mount_roll_yaw = cfg["mount_roll_yaw"]
    m.tilt = float(cfg["tilt_deg"])
    lo, hi = cfg["elevation_min_deg"], cfg["elevation_max_deg"]
    tx = np.asarray(msg.ping_info.tx_beamwidths, dtype=np.float32)
    if len(tx) > 0 and np.isfinite(tx[0]) and tx[0] > 0 and abs(float(tx[0]) - float(hi - lo)) > 1e-6:
        lo, hi = -tx[0] / np.float32(2), tx[0] / np.float32(2)  # the bag's aperture, centred
    m.elevation_min, m.elevation_max = float(lo), float(hi)
    m.num_beams = len(cols)
    m.beam_bearing = [float(np.float32(b)) for b in bearing[cols]]
    m.num_ranges = len(rows)
    m.row_range = [float(r) for r in ranges[rows]]
    m.data = np.ascontiguousarray(u8[rows][:, cols]).tobytes()
    m.data_size = len(m.data)
    return m


def ros_to_ps(L, msg, topic, idx, cfg, fscale):
    arr, ranges, dirs = _image(msg, topic, idx)
    if arr.shape[1] != 1:
        raise BagError(f"{topic} message {idx}: a profiling-sonar ping must have one beam, has {arr.shape[1]}")
    u8 = to_uint8(arr[:, 0], int(msg.image.dtype), fscale)
    order = np.argsort(ranges, kind="stable")
    ranges, u8 = ranges[order], u8[order]
    n = len(ranges)
    if n > 2:  # ps_ping_t has uniform bins: resample a non-uniform ping (nearest bin)
        grid = ranges[0] + (ranges[-1] - ranges[0]) * np.arange(n) / (n - 1)
        step = (ranges[-1] - ranges[0]) / (n - 1)
        if np.max(np.abs(ranges.astype(np.float64) - grid)) > 1e-3 * step + 1e-5:
            hi = np.clip(np.searchsorted(ranges, grid), 1, n - 1)
            lo = hi - 1
            nearest = np.where(np.abs(grid - ranges[lo]) <= np.abs(ranges[hi] - grid), lo, hi)
            u8 = u8[nearest]
    m = L.ps_ping_t()
    m.utime = utime_of(msg.header.stamp)
    m.sensor_name = msg.header.frame_id
    m.mount_xyz = cfg["mount_xyz"]
    m.mount_roll_yaw = cfg["mount_roll_yaw"]
    m.tilt = float(cfg["tilt_deg"])
    m.head_angle = float(np.float32(math.atan2(-dirs[0, 0], dirs[0, 2])))  # + looks down (-X)
    lo, hi = cfg["fan_min_deg"], cfg["fan_max_deg"]
    rx = np.asarray(msg.ping_info.rx_beamwidths, dtype=np.float32)
    if len(rx) > 0 and np.isfinite(rx[0]) and rx[0] > 0 and abs(float(rx[0]) - float(hi - lo)) > 1e-6:
        lo, hi = -rx[0] / np.float32(2), rx[0] / np.float32(2)
    m.fan_min, m.fan_max = float(lo), float(hi)
    m.range_min, m.range_max = float(ranges[0]), float(ranges[-1])
    m.num_bins = n
    m.intensity = u8.tobytes()
    return m


def ros_to_nav(L, msg, msgtype, topic, idx):
    if msgtype == rosmsgs.ODOM:
        pose, lin = msg.pose.pose, msg.twist.twist.linear
        v = (lin.x, lin.y, lin.z)
    else:
        pose, v = msg.pose, (0.0, 0.0, 0.0)
    vals = (pose.position.x, pose.position.y, pose.position.z, pose.orientation.x, pose.orientation.y,
            pose.orientation.z, pose.orientation.w) + tuple(v)
    if not all(math.isfinite(x) for x in vals):
        raise BagError(f"{topic} message {idx}: non-finite pose or velocity")
    try:
        p, rpy, vn = frames.enu_flu_to_ned_frd((pose.position.x, pose.position.y, pose.position.z),
                                               (pose.orientation.x, pose.orientation.y, pose.orientation.z,
                                                pose.orientation.w), v)
    except ValueError as e:
        raise BagError(f"{topic} message {idx}: {e}") from None
    m = L.nav_state_t()
    m.utime = utime_of(msg.header.stamp)
    m.position_ned = list(p)
    m.rpy = list(rpy)
    m.velocity_ned = list(vn)
    m.altitude = -1.0  # unknown: neither message carries it
    return m


def apply_exact_nav(m, e, topic, idx, exact_topic):
    """Replaces the NAV converted from Odometry by the exact values of the
    companion message with its stamp, once they are checked to agree."""
    def ang(a, b):
        return abs(math.remainder(a - b, 2 * math.pi))
    if not (max(abs(a - b) for a, b in zip(m.position_ned, e.position_ned)) <= 1e-6
            and max(ang(a, b) for a, b in zip(m.rpy, e.rpy)) <= 1e-9):
        raise BagError(f"{topic} message {idx}: disagrees with {exact_topic} at the same stamp "
                       f"(position {list(m.position_ned)} vs {list(e.position_ned)}, rpy {list(m.rpy)} vs {list(e.rpy)})")
    m.position_ned = [float(x) for x in e.position_ned]
    m.rpy = [float(x) for x in e.rpy]
    m.velocity_ned = [float(x) for x in e.velocity_ned]
    m.altitude = float(e.altitude)


def import_bag(bag, out_log, topics=None, channels=None, config=None, float_full_scale=1.0, quiet=False):
    from rosbags.highlevel import AnyReader, AnyReaderError

    topics = dict(DEFAULT_TOPICS, **(topics or {}))
    channels = channels or {"fls": "FLS", "ps": "PS", "nav": "NAV"}
    cfg = load_sensor_config(config)
    L = lcmlog.types()
    ts = rosmsgs.typestore()
    exact_topic = topics.pop("nav_ned", "")
    want = {k: t for k, t in topics.items() if t}  # an empty topic name leaves that sensor out
    if not want:
        raise BagError("no topic to import")
    accept = {"fls": {rosmsgs.PSI}, "ps": {rosmsgs.PSI}, "nav": {rosmsgs.ODOM, rosmsgs.POSE}}
    events = []  # (utime, rank, index, channel, bytes)
    counts = {k: 0 for k in want}
    out_of_order = {k: 0 for k in want}
    try:
        reader = AnyReader([Path(bag)], default_typestore=ts)
    except (AnyReaderError, FileNotFoundError) as e:
        raise BagError(f"{bag}: cannot open as a bag: {e}") from None
    with reader:
        have = {}
        for c in reader.connections:
            have.setdefault(c.topic, []).append(c)
        kind_of = {}
        for kind, topic in want.items():
            if topic not in have:
                listing = ", ".join(f"{t} ({cs[0].msgtype})" for t, cs in sorted(have.items())) or "none"
                raise BagError(f"{bag}: no topic {topic} for the {kind.upper()} (--{kind}-topic); the bag has: {listing}")
            for c in have[topic]:
                if c.msgtype not in accept[kind]:
                    raise BagError(f"{bag}: topic {topic} is {c.msgtype}; the {kind.upper()} needs "
                                   + " or ".join(sorted(accept[kind])))
                kind_of[c.id] = kind
        exact_conns = [c for c in have.get(exact_topic, []) if c.msgtype == rosmsgs.NAVSTATE] \
            if "nav" in want and exact_topic else []
        conns = [c for c in reader.connections if c.id in kind_of] + exact_conns
        exact_ids = {c.id for c in exact_conns}
        exact = {}  # utime -> exact nav_state_t values (sf-bag export's companion topic)
        newest = {k: None for k in want}
        for conn, _t, raw in reader.messages(connections=conns):
            if conn.id in exact_ids:
                e = reader.deserialize(raw, conn.msgtype)
                exact[utime_of(e.header.stamp)] = e
                continue
            kind = kind_of[conn.id]
            topic = want[kind]
            idx = counts[kind]
            counts[kind] += 1
            try:
                msg = reader.deserialize(raw, conn.msgtype)
            except Exception as e:  # noqa: BLE001 - any decoding failure names the message
                raise BagError(f"{topic} message {idx}: cannot deserialize ({e})") from None
            if kind == "nav":
                m = ros_to_nav(L, msg, conn.msgtype, topic, idx)
            elif kind == "fls":
                m = ros_to_fls(L, msg, topic, idx, cfg["fls"], float_full_scale)
            else:
                m = ros_to_ps(L, msg, topic, idx, cfg["ps"], float_full_scale)
            if newest[kind] is not None and m.utime < newest[kind]:
                out_of_order[kind] += 1
            newest[kind] = m.utime if newest[kind] is None else max(newest[kind], m.utime)
            events.append((m.utime, RANK[kind], idx, kind, m))
    for kind, n in counts.items():
        if n == 0:
            raise BagError(f"{bag}: topic {want[kind]} has no messages")
    exact_used = 0
    if exact:
        for _utime, _rank, idx, kind, m in events:
            if kind == "nav" and m.utime in exact:
                apply_exact_nav(m, exact[m.utime], want["nav"], idx, exact_topic)
                exact_used += 1
    events.sort(key=lambda e: e[:3])
    seq = {k: 0 for k in want}
    with lcmlog.LogWriter(out_log) as w:
        for utime, _rank, _idx, kind, m in events:
            m.seq = seq[kind]
            seq[kind] += 1
            w.write(utime, channels[kind], m.encode())
        w.commit()
    if not quiet:
        print(f"sf-bag import: {out_log}: " + ", ".join(
            f"{channels[k]} {counts[k]} from {want[k]}" + (f" ({out_of_order[k]} out of order, sorted)"
                                                           if out_of_order[k] else "")
            for k in ("nav", "fls", "ps") if k in want)
              + (f"; exact NED values from {exact_topic} for {exact_used} NAV" if exact_used else ""))
    return counts, out_of_order
