#!/usr/bin/env python3
"""Baseline for `cargo bench -p dualspectra --bench eigensolver`: scipy's ARPACK
shift-invert `eigsh(W, k, M, sigma, which='LM')` on the same pencil the Rust bench solves.

Input (written by the bench): a little-endian binary file
    u64 n, u64 nnz, u64 k, f64 sigma,
    u64 col_ptr[n+1], u64 row_idx[nnz], f64 values[nnz], f64 mass[n]
(W in compressed sparse column form, M = diag(mass)).

Output on stdout, one `key value...` per line:
    seconds <best wall time of the repeats, factorisation included>
    values <the k eigenvalues, ascending>
"""
import sys
import time

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh


def read_pencil(path):
    raw = open(path, "rb").read()
    n, nnz, k = np.frombuffer(raw, dtype="<u8", count=3, offset=0)
    n, nnz, k = int(n), int(nnz), int(k)
    sigma = float(np.frombuffer(raw, dtype="<f8", count=1, offset=24)[0])
    off = 32
    col_ptr = np.frombuffer(raw, dtype="<u8", count=n + 1, offset=off).astype(np.int64)
    off += 8 * (n + 1)
    row_idx = np.frombuffer(raw, dtype="<u8", count=nnz, offset=off).astype(np.int64)
    off += 8 * nnz
    values = np.frombuffer(raw, dtype="<f8", count=nnz, offset=off)
    off += 8 * nnz
    mass = np.frombuffer(raw, dtype="<f8", count=n, offset=off)
    w = sp.csc_matrix((values, row_idx, col_ptr), shape=(n, n))
    return w, mass, k, sigma


def main():
    if len(sys.argv) < 2:
        print("usage: bench_scipy_eigsh.py PENCIL_FILE [REPEATS]", file=sys.stderr)
        return 2
    w, mass, k, sigma = read_pencil(sys.argv[1])
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    m = sp.diags(mass).tocsc()
    best = float("inf")
    vals = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        vals, _vecs = eigsh(w, k=k, M=m, sigma=sigma, which="LM")
        best = min(best, time.perf_counter() - t0)
    print("seconds", repr(best))
    print("values", " ".join(repr(float(v)) for v in np.sort(vals)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
