"""tools/sf-bag: ROS 2 bags in and out (docs/ros2.md)."""

import argparse
import os
import sys

from . import convert, lcmlog

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main(argv=None):
    ap = argparse.ArgumentParser(prog="sf-bag", description="ROS 2 bags <-> sonarfusion LCM logs (docs/ros2.md)")
    sub = ap.add_subparsers(dest="cmd", required=True)
    im = sub.add_parser("import", help="ROS 2 bag (sqlite3 or MCAP folder) -> LCM log for sf-mapper --log")
    im.add_argument("bag")
    im.add_argument("out_log")
    for k in ("fls", "ps", "nav"):
        im.add_argument(f"--{k}-topic", default=convert.DEFAULT_TOPICS[k],
                        help=f"default {convert.DEFAULT_TOPICS[k]}; '' leaves the {k.upper()} out")
    im.add_argument("--nav-ned-topic", default=convert.DEFAULT_TOPICS["nav_ned"],
                    help="sonarfusion_msgs/NavState beside the NAV (written by export): its exact NED values "
                         "replace the Odometry's where stamps match, once checked to agree; '' ignores it")
    im.add_argument("--config", default=os.path.join(ROOT, "scenarios", "mapper.yaml"),
                    help="mapper config (or scenario) giving the tilts, mountings, PS fan and default FLS aperture "
                         "that a ProjectedSonarImage does not carry (default scenarios/mapper.yaml)")
    im.add_argument("--float-full-scale", type=float, default=1.0,
                    help="float32/float64 images: the value mapped to 255 (default 1.0)")
    ex = sub.add_parser("export", help="LCM log -> ROS 2 bag")
    ex.add_argument("log")
    ex.add_argument("out_bag")
    ex.add_argument("--storage", choices=("sqlite3", "mcap"), default="sqlite3")
    for p in (im, ex):
        for k in ("fls", "ps", "nav"):
            p.add_argument(f"--{k}-channel", default=k.upper(), help=f"LCM channel (default {k.upper()})")
        p.add_argument("--quiet", action="store_true")
    if argv is None:
        argv = sys.argv[1:]
    a = ap.parse_args(argv)
    channels = {k: getattr(a, f"{k}_channel") for k in ("fls", "ps", "nav")}
    try:
        if a.cmd == "export":
            convert.export(a.log, a.out_bag, a.storage, channels=channels, quiet=a.quiet)
        else:
            if not os.path.exists(a.bag):
                raise convert.BagError(f"{a.bag}: no such bag")
            convert.import_bag(a.bag, a.out_log, topics={k: getattr(a, f"{k}_topic") for k in ("fls", "ps", "nav", "nav_ned")},
                               channels=channels, config=a.config, float_full_scale=a.float_full_scale,
                               quiet=a.quiet)
    except (convert.BagError, lcmlog.LogError, OSError) as e:
        print(f"sf-bag {a.cmd}: error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
