#!/usr/bin/python3
"""How well each simulated garment of a data set stays on its body.

    /usr/bin/python3 scripts/dataset_stats.py ~/.cache/pleat/datasets/pleat-demo-v2 [--every 5]

For every sequence folder (meta.json, body.pc2, garment.pc2, garment.obj) it
prints, over every --every-th frame: the mean and the worst share of garment
vertices more than 10 cm from the nearest body vertex (a tight garment that
Blender let slip off has many; docs/datagen.md#quality-steps-why-24), the
mean and the worst share of vertices that "slipped": moved more than 15 cm
further from the body vertex they were nearest on the first frame (a sleeve
the arm went through, a jacket that slid off the shoulders; docs/datagen.md,
"Garments that come off"), the furthest vertex, and the mean edge strain
against the rest garment. The datagen check rejects a sequence on its
furthest vertex only; this is the survey behind the quality setting. Needs
python3-numpy and python3-scipy.
"""
import argparse
import os
import sys

import numpy as np
from scipy.spatial import cKDTree


def read_pc2(path):
    with open(path, "rb") as f:
        header = f.read(32)
        if header[:12] != b"POINTCACHE2\0":
            sys.exit("%s: not a PC2 file" % path)
        points = int(np.frombuffer(header[16:20], np.int32)[0])
        samples = int(np.frombuffer(header[28:32], np.int32)[0])
        data = np.frombuffer(f.read(), np.float32)
    if data.size != samples * points * 3:
        sys.exit("%s: %d floats for %d samples of %d points" % (path, data.size, samples, points))
    return data.reshape(samples, points, 3)


def rest_edges(obj_path):
    vertices, edges = [], set()
    with open(obj_path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                face = [int(t.split("/")[0]) - 1 for t in line.split()[1:]]
                for a, b in zip(face, face[1:] + face[:1]):
                    edges.add((min(a, b), max(a, b)))
    return np.array(vertices), np.array(sorted(edges))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dataset")
    parser.add_argument("--every", type=int, default=5, help="frame stride (default 5)")
    parser.add_argument("--far", type=float, default=0.1, help="'far' distance in m (default 0.1)")
    parser.add_argument("--slip", type=float, default=0.15,
                        help="'slipped' distance in m, beyond the first frame's (default 0.15)")
    args = parser.parse_args()
    names = sorted(n for n in os.listdir(args.dataset)
                   if os.path.exists(os.path.join(args.dataset, n, "meta.json")))
    if not names:
        sys.exit("%s: no sequence folder (with meta.json) in it" % args.dataset)
    print("%-45s %6s %9s %9s %10s %10s %8s %7s" % ("sequence", "frames", "far mean", "far worst", "slip mean",
                                                    "slip worst", "furthest", "strain"))
    for name in names:
        folder = os.path.join(args.dataset, name)
        body = read_pc2(os.path.join(folder, "body.pc2"))
        garment = read_pc2(os.path.join(folder, "garment.pc2"))
        rest, edges = rest_edges(os.path.join(folder, "garment.obj"))
        rest_length = np.linalg.norm(rest[edges[:, 0]] - rest[edges[:, 1]], axis=1)
        far, slipped, furthest, strain = [], [], 0.0, []
        # Each vertex against the body vertex nearest it on the first frame:
        # a sleeve stays near its arm however the arm moves; one the arm went
        # through is left behind.
        first_distance, anchor = cKDTree(body[0]).query(garment[0])
        for f in range(0, garment.shape[0], args.every):
            distance, _ = cKDTree(body[f]).query(garment[f])
            far.append(np.mean(distance > args.far))
            furthest = max(furthest, float(distance.max()))
            from_anchor = np.linalg.norm(garment[f] - body[f][anchor], axis=1)
            slipped.append(np.mean(from_anchor - first_distance > args.slip))
            length = np.linalg.norm(garment[f][edges[:, 0]] - garment[f][edges[:, 1]], axis=1)
            strain.append(np.mean(np.abs(length - rest_length) / rest_length))
        print("%-45s %6d %8.1f%% %8.1f%% %9.1f%% %9.1f%% %7.3fm %6.1f%%" %
              (name, garment.shape[0], 100 * np.mean(far), 100 * np.max(far), 100 * np.mean(slipped),
               100 * np.max(slipped), furthest, 100 * np.mean(strain)))


if __name__ == "__main__":
    main()
