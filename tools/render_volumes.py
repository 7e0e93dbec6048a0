#!/usr/bin/env python3
"""Renders fcl_rs_export's volumes with f3d (VTK, depth peeling) instead of gnuplot's painter's algorithm.

  python3 tools/render_volumes.py MESH.obj --bv RS,OBB,KDOP18 --level 3 --out volumes.png
  python3 tools/render_volumes.py --shape paper-sphere --bv kIOS,OBB,KDOP18,RS --level 0 --out fig9.png

One panel per BV type: fcl_rs_export writes the type's glTF and prints its caption (type, level, depth, number
of volumes, volume/hull), f3d renders it offscreen under xvfb-run (f3d crashes without a display), and
ImageMagick trims them and its montage puts the panels side by side with the captions as the legend. Every panel has the same
camera: looking at the mesh's centroid along its axis of least spread (principal axes of its vertices), the
axis of most spread horizontal, so the mesh is seen from the front rather than along whatever axis the file
happens to use. Needs f3d, xvfb and imagemagick (scripts/setup.sh installs them for the tools).
"""

import argparse
import math
import os
import subprocess
import sys
import tempfile


def run(command):
    """Runs command; on failure exits with its own error message rather than a traceback."""
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit("render_volumes: %s failed: %s" % (command[0], (done.stderr or done.stdout).strip()))
    return done


def mesh_vertices(path):
    """The vertices of fcl_rs_export's OBJ that the faces of its group "mesh" use."""
    vertices, used, group = [], set(), None
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append(tuple(float(x) for x in line.split()[1:4]))
            elif line.startswith("g "):
                group = line[2:].strip()
            elif line.startswith("f ") and group == "mesh":
                used.update(int(w.split("/")[0]) - 1 for w in line.split()[1:])
    return [vertices[i] for i in sorted(used)]


def jacobi_eigen(a):
    """Eigenvalues and column eigenvectors of a symmetric 3x3 matrix (cyclic Jacobi)."""
    a = [row[:] for row in a]
    v = [[float(i == j) for j in range(3)] for i in range(3)]
    for _ in range(50):
        off = sum(a[i][j] ** 2 for i in range(3) for j in range(3) if i != j)
        if off < 1e-30:
            break
        for p, q in ((0, 1), (0, 2), (1, 2)):
            if abs(a[p][q]) < 1e-300:
                continue
            theta = (a[q][q] - a[p][p]) / (2 * a[p][q])
            t = math.copysign(1.0, theta) / (abs(theta) + math.sqrt(theta * theta + 1))
            c = 1 / math.sqrt(t * t + 1)
            s = t * c
            for k in range(3):  # A <- A J
                akp, akq = a[k][p], a[k][q]
                a[k][p], a[k][q] = c * akp - s * akq, s * akp + c * akq
            for k in range(3):  # A <- J^T A
                apk, aqk = a[p][k], a[q][k]
                a[p][k], a[q][k] = c * apk - s * aqk, s * apk + c * aqk
            for k in range(3):
                vkp, vkq = v[k][p], v[k][q]
                v[k][p], v[k][q] = c * vkp - s * vkq, s * vkp + c * vkq
    return [a[i][i] for i in range(3)], [[v[k][i] for k in range(3)] for i in range(3)]


def front_camera(vertices):
    """Focal point, camera position and view-up: along the least-spread axis, the most-spread one horizontal.
    An axis's sign is chosen so that the vertices' third moment along it is positive: the same view on every run
    and for every panel."""
    n = len(vertices)
    centre = [sum(p[i] for p in vertices) / n for i in range(3)]
    d = [[p[i] - centre[i] for i in range(3)] for p in vertices]
    cov = [[sum(x[i] * x[j] for x in d) / n for j in range(3)] for i in range(3)]
    values, vectors = jacobi_eigen(cov)
    order = sorted(range(3), key=lambda i: values[i])
    axes = []
    for i in order:
        axis = vectors[i]
        skew = sum(sum(x[k] * axis[k] for k in range(3)) ** 3 for x in d)
        axes.append([-c for c in axis] if skew < 0 else axis)
    least, middle, _ = axes
    radius = max(math.sqrt(sum(c * c for c in x)) for x in d)
    position = [centre[i] + 6 * radius * least[i] for i in range(3)]
    return centre, position, middle


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("mesh", nargs="?", help="a mesh file fcl_rs_export reads")
    source.add_argument("--shape", help="one of fcl_rs_export's built-in shapes instead")
    parser.add_argument("--bv", default="RS,OBB,KDOP18", help="comma-separated BV types, one panel each")
    parser.add_argument("--level", type=int, default=3)
    parser.add_argument("--out", required=True, help="the PNG to write")
    parser.add_argument("--export", default=os.path.join("build", "tools", "fcl_rs_export"),
                        help="the fcl_rs_export program")
    parser.add_argument("--size", type=int, default=400, help="panel width and height in pixels")
    args = parser.parse_args()

    source = [args.mesh] if args.mesh else ["--shape", args.shape]
    triple = lambda v: ",".join("%.9g" % c for c in v)
    panels = []
    with tempfile.TemporaryDirectory() as tmp:
        obj = os.path.join(tmp, "mesh.obj")
        run([args.export, *source, "--bv", "AABB", "--level", "0", "--out", obj])
        focal, position, up = front_camera(mesh_vertices(obj))
        for bv in args.bv.split(","):
            glb = os.path.join(tmp, bv + ".glb")
            png = os.path.join(tmp, bv + ".png")
            out = run([args.export, *source, "--bv", bv, "--level", str(args.level), "--out", glb])
            caption = next(line for line in out.stdout.splitlines() + out.stderr.splitlines() if "volume/hull" in line)
            run(["xvfb-run", "-a", "f3d", glb, "--output=" + png, "--resolution=%d,%d" % (args.size, args.size),
                            "--depth-peeling", "--bg-color=1,1,1", "--camera-focal-point=" + triple(focal),
                            "--camera-position=" + triple(position), "--camera-view-up=" + triple(up)])
            if not os.path.exists(png):
                sys.exit("render_volumes: f3d wrote no %s" % png)
            # The camera is far enough for the widest volume; the white margin around the drawing goes.
            run(["convert", png, "-trim", "+repage", "-bordercolor", "white", "-border", "8", png])
            panels += ["-label", caption, png]
        run(["montage", *panels, "-tile", "%dx1" % (len(panels) // 3), "-geometry", "+4+4", "-pointsize", "13",
             args.out])
    print("wrote", args.out)


if __name__ == "__main__":
    main()
