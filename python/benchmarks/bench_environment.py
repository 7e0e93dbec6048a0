#!/usr/bin/env python3
"""What a Python planner pays per call: fcl_rs.Environment's single calls against its batches on one thread.

  python3 bench_environment.py ROBOT.urdf ROBOT.srdf [-n 2000] [--segments 100] [--rounds 5]

The scene of python/examples/environment.py (a table, a post, a scanned ball as an octomap). Per configuration:
env.query(q) called once per row against env.check_batch(rows, num_threads=1) (the C++ loop behind one call);
per segment: env.check_motion against env.check_motion_batch(num_threads=1), segments from collision-free
configurations with every joint moving within +-0.3. Thread CPU time, rounds interleaved; the minimum and the
largest of each. The difference is the binding's cost per call (argument checks, the GIL released and taken, the
world lock, the result dict).
"""
import argparse
import os
import time

import numpy as np

import fcl_rs


def at(x, y, z):
    pose = np.eye(4)
    pose[:3, 3] = (x, y, z)
    return pose


def scene(urdf, srdf):
    env = fcl_rs.Environment(urdf, srdf)
    env.add_shape("table", fcl_rs.Box(0.8, 1.2, 0.04), at(0.6, 0.0, 0.2))
    env.add_shape("post", fcl_rs.Cylinder(0.03, 0.8), at(0.35, -0.35, 0.6))
    rng = np.random.default_rng(1)
    ball = rng.normal(size=(500, 3))
    ball = 0.05 * ball / np.linalg.norm(ball, axis=1, keepdims=True) + [0.26, 0.17, 0.5]
    env.add_octree("scan", fcl_rs.OcTree(ball, resolution=0.02), np.eye(4))
    return env


def timed(call):
    start = time.thread_time()
    result = call()
    return time.thread_time() - start, result


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("urdf")
    parser.add_argument("srdf")
    parser.add_argument("-n", type=int, default=2000, help="configurations")
    parser.add_argument("--segments", type=int, default=100)
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    env = scene(args.urdf, args.srdf)
    rng = np.random.default_rng(2)
    q = rng.uniform(env.lower, env.upper, (args.n, env.dof))
    free = q[~env.check_batch(q)["colliding"]][: args.segments]
    ends = np.clip(free + rng.uniform(-0.3, 0.3, free.shape), env.lower, env.upper)
    print(f"load average before: {os.getloadavg()}; {len(q)} configurations, {len(free)} segments")
    times = {"query": [], "check_batch": [], "check_motion": [], "check_motion_batch": []}
    for _ in range(args.rounds):
        t, single = timed(lambda: [env.query(row)["colliding"] for row in q])
        times["query"].append(t)
        t, batch = timed(lambda: env.check_batch(q, num_threads=1)["colliding"])
        times["check_batch"].append(t)
        assert np.array_equal(single, batch)
        t, single = timed(lambda: [env.check_motion(a, b)["colliding"] for a, b in zip(free, ends)])
        times["check_motion"].append(t)
        t, batch = timed(lambda: env.check_motion_batch(free, ends, num_threads=1)["colliding"])
        times["check_motion_batch"].append(t)
        assert np.array_equal(single, batch)
    for name, count in [("query", len(q)), ("check_batch", len(q)), ("check_motion", len(free)),
                        ("check_motion_batch", len(free))]:
        print(f"{name}: {1e6 * min(times[name]) / count:.2f} us per call/row "
              f"(largest round {1e6 * max(times[name]) / count:.2f})")
    for single, batch, count in [("query", "check_batch", len(q)), ("check_motion", "check_motion_batch", len(free))]:
        print(f"{single} over {batch}: +{1e6 * (min(times[single]) - min(times[batch])) / count:.2f} us per call, "
              f"ratio {min(times[single]) / min(times[batch]):.3f}")
    print(f"load average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
