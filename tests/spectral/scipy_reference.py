"""Reference band basis from SciPy, for test_spectral_scipy.

usage: scipy_reference.py EDGES POSITIONS VERTEX_COUNT COUNT LOW MID OUTDIR
EDGES: "a b" per line; POSITIONS: "x y z" per line. Builds L_norm with
scipy.sparse (isolated vertices: zero row), takes the COUNT lowest eigenpairs
from LAPACK through scipy.linalg.eigh on the dense matrix (the test graph is
small; ARPACK's eigsh was tried first and can skip one copy of a repeated
eigenvalue of the sphere, depending on the machine), and writes eigenvalues.txt plus the random-walk low and
mid bands (cuts LOW, MID) of the positions as low.txt and mid.txt.
"""
import sys

import numpy as np
import scipy.sparse as sp
import scipy.linalg as sla_dense


def main():
    edges_path, positions_path, n, count, low, mid, outdir = sys.argv[1:8]
    n, count, low, mid = int(n), int(count), int(low), int(mid)
    edges = np.loadtxt(edges_path, dtype=np.int64, ndmin=2)
    x = np.loadtxt(positions_path, ndmin=2)
    rows = np.concatenate([edges[:, 0], edges[:, 1]])
    cols = np.concatenate([edges[:, 1], edges[:, 0]])
    c = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
    degree = np.asarray(c.sum(axis=1)).ravel()
    inv_sqrt = np.where(degree > 0, 1.0 / np.sqrt(np.maximum(degree, 1)), 0.0)
    identity = sp.diags((degree > 0).astype(float))
    lap = (identity - sp.diags(inv_sqrt) @ c @ sp.diags(inv_sqrt)).tocsc()
    values, vectors = sla_dense.eigh(lap.toarray(), subset_by_index=[0, count - 1])
    sqrt_degree = np.where(degree > 0, np.sqrt(degree), 1.0)
    scaled = sqrt_degree[:, None] * x
    low_band = vectors[:, :low] @ (vectors[:, :low].T @ scaled) / sqrt_degree[:, None]
    mid_band = vectors[:, low:mid] @ (vectors[:, low:mid].T @ scaled) / sqrt_degree[:, None]
    np.savetxt(f"{outdir}/eigenvalues.txt", values, fmt="%.17g")
    np.savetxt(f"{outdir}/low.txt", low_band, fmt="%.17g")
    np.savetxt(f"{outdir}/mid.txt", mid_band, fmt="%.17g")


if __name__ == "__main__":
    main()
