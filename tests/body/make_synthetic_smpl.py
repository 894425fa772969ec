#!/usr/bin/env python3
"""Writes small random SMPL-layout .npz files and reference results for
tests/test_smpl_npz.cpp. Usage: make_synthetic_smpl.py OUT_DIR

The reference posed vertices are computed here with an independent numpy
implementation of the SMPL formulas (Loper et al. 2015):
  v_shaped = v_template + shapedirs . beta
  J        = J_regressor . v_shaped
  v_posed  = v_shaped + posedirs . concat_j>=1 (R(theta_j) - I).ravel()
  G_j      = G_parent(j) [R_j | J_j - J_parent(j)],  A_j = G_j translate(-J_j)
  v        = sum_j w_vj A_j v_posed + trans
No SMPL data is used: every array is random.
"""
import os
import sys

import numpy as np

V, J, B = 60, 5, 4
PARENTS = [-1, 0, 1, 1, 3]


def rodrigues(aa):
    theta = np.linalg.norm(aa)
    if theta < 1e-12:
        return np.eye(3)
    k = aa / theta
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(theta) * K + (1 - np.cos(theta)) * K @ K


def smpl_forward(m, beta, pose, trans):
    v_template = m["v_template"].astype(np.float64)
    shapedirs = m["shapedirs"].astype(np.float64)
    posedirs = m["posedirs"].astype(np.float64)
    jreg = m["J_regressor"].astype(np.float64)
    weights = m["weights"].astype(np.float64)
    parents = m["kintree_table"][0].astype(np.int64)
    parents[parents == 4294967295] = -1
    nb = len(beta)
    v_shaped = v_template + shapedirs[:, :, :nb] @ beta
    joints = jreg @ v_shaped
    rots = np.stack([rodrigues(pose[j]) for j in range(J)])
    feature = (rots[1:] - np.eye(3)).reshape(-1)
    v_posed = v_shaped + posedirs @ feature
    G = np.zeros((J, 4, 4))
    for j in range(J):
        local = np.eye(4)
        local[:3, :3] = rots[j]
        local[:3, 3] = joints[j] - (joints[parents[j]] if parents[j] >= 0 else 0)
        G[j] = local if parents[j] < 0 else G[parents[j]] @ local
    A = G.copy()
    for j in range(J):
        A[j, :3, 3] -= G[j, :3, :3] @ joints[j]
    T = np.einsum("vj,jab->vab", weights, A)
    homo = np.concatenate([v_posed, np.ones((V, 1))], axis=1)
    posed = np.einsum("vab,vb->va", T, homo)[:, :3] + trans
    return posed, joints, v_shaped


def random_model(rng):
    v_template = rng.normal(size=(V, 3))
    shapedirs = rng.normal(scale=0.05, size=(V, 3, B))
    posedirs = rng.normal(scale=0.01, size=(V, 3, 9 * (J - 1)))
    jreg = rng.uniform(size=(J, V)) * (rng.uniform(size=(J, V)) < 0.3)
    jreg /= jreg.sum(axis=1, keepdims=True)
    weights = rng.uniform(size=(V, J)) * (rng.uniform(size=(V, J)) < 0.6)
    weights[np.arange(V), rng.integers(0, J, size=V)] += 0.5  # nobody unweighted
    weights /= weights.sum(axis=1, keepdims=True)
    kintree = np.array([PARENTS, list(range(J))], dtype=np.int64)
    faces = np.array([[i, (i + 1) % V, (i + 7) % V] for i in range(V - 2)])
    return dict(v_template=v_template, shapedirs=shapedirs, posedirs=posedirs, J_regressor=jreg,
                weights=weights, kintree_table=kintree, f=faces)


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    rng = np.random.default_rng(1234)
    base = random_model(rng)

    # Compressed: float64 / int64 with root -1, extra unused arrays (one of
    # object dtype, as real files carry) and C order.
    compressed = dict(base)
    compressed["f"] = base["f"].astype(np.uint32)
    compressed["J"] = base["J_regressor"] @ base["v_template"]
    compressed["notes"] = np.array(["an object array pleat must skip"], dtype=object)
    np.savez_compressed(os.path.join(out, "smpl_compressed.npz"), **compressed)

    # Stored: float32 / Fortran order / uint32 kintree with root 4294967295.
    plain = dict(base)
    plain["v_template"] = base["v_template"].astype(np.float32)
    plain["shapedirs"] = np.asfortranarray(base["shapedirs"].astype(np.float32))
    plain["posedirs"] = np.asfortranarray(base["posedirs"])
    plain["J_regressor"] = np.asfortranarray(base["J_regressor"].astype(np.float32))
    plain["weights"] = base["weights"].astype(np.float32)
    plain["kintree_table"] = np.array([[4294967295] + PARENTS[1:], list(range(J))], dtype=np.uint32)
    plain["f"] = base["f"].astype(np.int32)
    np.savez(os.path.join(out, "smpl_plain.npz"), **plain)

    beta = np.array([0.7, -1.2, 0.4])  # fewer than B: the rest are zero
    pose = rng.normal(scale=0.6, size=(J, 3))
    trans = np.array([0.3, -0.1, 0.25])
    ref = dict(beta=beta, pose=pose, trans=trans)
    for name, m in (("compressed", compressed), ("plain", plain)):
        posed, joints, shaped = smpl_forward(m, beta, pose, trans)
        ref["posed_" + name] = posed
        ref["joints_" + name] = joints
        ref["shaped_" + name] = shaped
    np.savez(os.path.join(out, "reference.npz"), **ref)

    # Bad inputs, each from the compressed model with one fault.
    def bad(name, **changes):
        m = dict(compressed)
        for k, v in changes.items():
            if v is None:
                del m[k]
            else:
                m[k] = v
        np.savez(os.path.join(out, name + ".npz"), **m)

    bad("missing_weights", weights=None)
    bad("bad_shapedirs", shapedirs=base["shapedirs"][: V - 1])
    bad("bad_posedirs", posedirs=base["posedirs"][:, :, :-9])
    nan = base["v_template"].copy()
    nan[7, 1] = np.nan
    bad("nan_template", v_template=nan)
    w = base["weights"].copy()
    w[13] *= 0.8
    bad("weights_sum", weights=w)
    cyc = base["kintree_table"].copy()
    cyc[0] = [-1, 0, 4, 1, 2]  # 2 -> 4 -> 2
    bad("kintree_cycle", kintree_table=cyc)
    badf = base["f"].copy()
    badf[5, 2] = V + 3
    bad("face_range", f=badf)
    bad("bad_dtype", weights=base["weights"].astype(np.complex64))

    # The .npy reader on its own: every supported dtype, C and Fortran order,
    # header versions 1 and 2, a scalar. Values are arange(24) - 5 (0/1 for bool).
    arrays = {}
    for dt in ("<f4", "<f8", "<i4", "<i8", "<u4", "<u8", "<i2", "<u2", "|i1", "|u1"):
        x = (np.arange(24) - (5 if dt[1] in "fi" else 0)).astype(dt).reshape(2, 3, 4)
        arrays["c_" + dt[1:]] = x
        arrays["f_" + dt[1:]] = np.asfortranarray(x)
    arrays["b1"] = (np.arange(6) % 2).astype(bool).reshape(2, 3)
    arrays["scalar"] = np.float64(2.5)
    arrays["empty"] = np.zeros((0, 3))
    np.savez_compressed(os.path.join(out, "dtypes.npz"), **arrays)
    with open(os.path.join(out, "v2.npy"), "wb") as fh:
        np.lib.format.write_array(fh, np.asfortranarray(arrays["c_f8"]), version=(2, 0))


if __name__ == "__main__":
    main()
