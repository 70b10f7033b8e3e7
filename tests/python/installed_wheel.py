"""The built wheel, installed into a fresh venv, imports and localizes (numpy only).

    python installed_wheel.py    # run by scripts/test.d/30-python.sh with the venv's python,
                                 # from outside the source tree

A square sheet with a hill on it and the hill as a mesh of its own (the README's example,
smaller): the region found must cover most of the hill and little else.
"""

import sys

import numpy as np

import dualspectra as ds

n = 24
x, y = (g.ravel() for g in np.meshgrid(np.linspace(-1, 1, n), np.linspace(-1, 1, n)))
V = np.c_[x, y, 0.4 * np.exp(-6 * ((x - 0.4) ** 2 + y**2))]
c = (np.arange(n - 1)[:, None] * n + np.arange(n - 1)).ravel()
F = np.r_[np.c_[c, c + 1, c + n + 1], np.c_[c, c + n + 1, c + n]]
hill = F[(np.hypot(x - 0.4, y)[F] < 0.5).all(axis=1)]
used, G = np.unique(hill, return_inverse=True)
P, G = V[used], G.reshape(-1, 3)

found = ds.localize(V, F, P, G, k=6, max_iterations=10)
truth = np.zeros(len(V), dtype=bool)
truth[used] = True
iou = (found.region & truth).sum() / (found.region | truth).sum()
print(f"dualspectra {ds.__version__} from {ds.__file__}: IoU {iou:.2f} on the hill "
      f"({found.region.sum()} of {len(V)} vertices), confidence {found.confidence:.2f}")
sys.exit(0 if found.region.shape == (len(V),) and iou > 0.5 else 1)
