"""A synthetic bag of a robot driving down a static corridor, for ``bench_real_bags.py``.

Run: ``python benchmarks/corridor_bag.py OUT.bag [--speed 0.6] [--noise 0.01] [--seed 0]``,
then ``python benchmarks/bench_real_bags.py OUT.bag`` (the ``ros`` extra).

Nothing in the corridor moves but the robot, so every confirmed track labelled moving is a
false alarm: the bag measures the real-bag benchmark's ``moving tracks per step`` on a
driving robot with its odometry, where no such public bag small enough to ship was found.
The scene, in the odometry frame (m): walls along y = ±2 from x = -5 to 20 and across at
x = 8, round posts at (3, 1.2), (4.5, -1.0) and (6, 0.8) of radius 0.10-0.15 m. The robot
starts at the origin heading +x and drives straight at ``--speed`` for 8 s (10 Hz scans); its
laser, 0.16 m ahead of its centre (the model's default mount), sweeps the front 180° in 360
beams to 5.6 m (a Hokuyo URG's range), each range scaled by 1 + ``--noise`` × N(0, 1);
``/odom`` carries the exact velocity at each scan's stamp.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

#: Wall segments ((x0, y0), (x1, y1)) and round posts (x, y, radius), m, odometry frame.
WALLS = (((-5.0, 2.0), (20.0, 2.0)), ((-5.0, -2.0), (20.0, -2.0)), ((8.0, -2.0), (8.0, 2.0)))
POSTS = ((3.0, 1.2, 0.10), (4.5, -1.0, 0.15), (6.0, 0.8, 0.12))
#: The laser: 360 beams over the front 180°, range limit (m), mount ahead of the centre (m).
BEAM_STEP_RAD = np.pi / 360
BEARINGS_RAD = -np.pi / 2 + BEAM_STEP_RAD * (np.arange(360) + 0.5)
RANGE_MAX_M = 5.6
MOUNT_X_M = 0.16
SCAN_PERIOD_S = 0.1
DURATION_S = 8.0
T0_NS = 1_700_000_000_000_000_000


def ranges(x_m: float, noise_rel: float, rng: np.random.Generator) -> np.ndarray:
    """``(360,)`` ranges (m) of the laser at ``x_m`` on the corridor's axis, heading +x; no
    echo within ``RANGE_MAX_M`` is +inf."""
    directions = np.stack([np.cos(BEARINGS_RAD), np.sin(BEARINGS_RAD)], axis=1)
    hit = np.full(len(BEARINGS_RAD), np.inf)
    origin = np.array([x_m, 0.0])
    for start, end in WALLS:
        a, edge = np.asarray(start) - origin, np.subtract(end, start)
        denominator = directions[:, 0] * edge[1] - directions[:, 1] * edge[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            along = (a[0] * edge[1] - a[1] * edge[0]) / denominator
            across = (a[0] * directions[:, 1] - a[1] * directions[:, 0]) / denominator
        crossed = (along > 0.0) & (across >= 0.0) & (across <= 1.0)
        hit = np.where(crossed, np.minimum(hit, along), hit)
    for x, y, radius in POSTS:
        centre = np.array([x, y]) - origin
        along = directions @ centre
        miss = radius**2 - (centre @ centre - along**2)
        front = (miss >= 0.0) & (along > 0.0)
        hit = np.where(front, np.minimum(hit, along - np.sqrt(np.maximum(miss, 0.0))), hit)
    hit = hit * (1.0 + noise_rel * rng.standard_normal(len(hit)))
    return np.where(hit < RANGE_MAX_M, hit, np.inf)


def write_corridor_bag(path: Path, speed_mps: float, noise_rel: float, seed: int = 0) -> int:
    """Write the corridor drive as a ROS 1 bag at ``path``; returns the number of scans."""
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC)
    types = store.types
    rng = np.random.default_rng(seed)
    n_scans = int(round(DURATION_S / SCAN_PERIOD_S))
    with Writer(path) as writer:
        scan_topic = writer.add_connection("/scan", "sensor_msgs/msg/LaserScan", typestore=store)
        odom_topic = writer.add_connection("/odom", "nav_msgs/msg/Odometry", typestore=store)
        for k in range(n_scans):
            stamp_ns = T0_NS + int(round(k * SCAN_PERIOD_S * 1e9))
            time = types["builtin_interfaces/msg/Time"](sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9)
            x_m = speed_mps * k * SCAN_PERIOD_S
            scan = types["sensor_msgs/msg/LaserScan"](
                header=types["std_msgs/msg/Header"](seq=k, stamp=time, frame_id="laser"),
                angle_min=float(BEARINGS_RAD[0]),
                angle_max=float(BEARINGS_RAD[-1]),
                angle_increment=BEAM_STEP_RAD,
                time_increment=0.0,
                scan_time=SCAN_PERIOD_S,
                range_min=0.02,
                range_max=RANGE_MAX_M,
                ranges=ranges(x_m + MOUNT_X_M, noise_rel, rng).astype(np.float32),
                intensities=np.zeros(0, np.float32),
            )
            vector = types["geometry_msgs/msg/Vector3"]
            odometry = types["nav_msgs/msg/Odometry"](
                header=types["std_msgs/msg/Header"](seq=k, stamp=time, frame_id="odom"),
                child_frame_id="base_link",
                pose=types["geometry_msgs/msg/PoseWithCovariance"](
                    pose=types["geometry_msgs/msg/Pose"](
                        position=types["geometry_msgs/msg/Point"](x=x_m, y=0.0, z=0.0),
                        orientation=types["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
                    ),
                    covariance=np.zeros(36),
                ),
                twist=types["geometry_msgs/msg/TwistWithCovariance"](
                    twist=types["geometry_msgs/msg/Twist"](
                        linear=vector(x=speed_mps, y=0.0, z=0.0), angular=vector(x=0.0, y=0.0, z=0.0)
                    ),
                    covariance=np.zeros(36),
                ),
            )
            writer.write(odom_topic, stamp_ns, store.serialize_ros1(odometry, "nav_msgs/msg/Odometry"))
            writer.write(scan_topic, stamp_ns, store.serialize_ros1(scan, "sensor_msgs/msg/LaserScan"))
    return n_scans


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, help="the bag to write (.bag); an existing file is not overwritten")
    parser.add_argument("--speed", type=float, default=0.6, help="the robot's speed (m/s, 0 to 2; default 0.6)")
    parser.add_argument("--noise", type=float, default=0.01, help="relative range noise σ (0 to 0.2; default 0.01)")
    parser.add_argument("--seed", type=int, default=0, help="the noise's seed (default 0)")
    args = parser.parse_args(argv)
    if not 0.0 <= args.speed <= 2.0:
        parser.error(f"--speed must be in [0, 2] m/s, got {args.speed:g}")
    if not 0.0 <= args.noise <= 0.2:
        parser.error(f"--noise must be in [0, 0.2], got {args.noise:g}")
    if args.out.suffix != ".bag":
        parser.error(f"the bag's name must end in .bag (ROS 1), got {args.out}")
    if args.out.exists():
        parser.error(f"{args.out} exists; remove it or name another")
    n_scans = write_corridor_bag(args.out, args.speed, args.noise, args.seed)
    print(f"wrote {args.out}: {n_scans} scans and odometry, driving at {args.speed:g} m/s, noise {args.noise:g}")


if __name__ == "__main__":
    main()
