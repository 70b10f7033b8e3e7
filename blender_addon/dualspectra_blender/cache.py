"""Prepared full shapes kept between runs, free of ``bpy``.

``dualspectra.Localizer(V, F, **options)`` prepares a full shape once (decimation, metric,
descriptors, factorization); locating a partial on it is then the only cost. Selecting
several parts on one model therefore keeps the prepared shape per full object, valid while
its world-space mesh and the options are what they were: :func:`fingerprint` hashes exactly
what the Localizer was built from (positions, triangles, options), a few milliseconds for a
mesh of 100k vertices, so any edit, transform or option change prepares anew.

Used from Blender's main thread only (the operator looks up before starting a job and
stores after it finished).
"""

import hashlib
import json
from collections import OrderedDict

import numpy as np


def fingerprint(vertices, faces, options):
    """A digest of ``vertices (n, 3)``, ``faces (m, 3)`` (as float64 / int64) and the options."""
    h = hashlib.blake2b(digest_size=16)
    for a, dtype in ((vertices, np.float64), (faces, np.int64)):
        a = np.ascontiguousarray(a, dtype=dtype)
        h.update(repr(a.shape).encode())
        h.update(a.tobytes())
    h.update(json.dumps(options, sort_keys=True).encode())
    return h.hexdigest()


class LocalizerCache:
    """At most ``capacity`` prepared shapes, one per key (a full object), least recently used
    dropped first. ``builds`` and ``hits`` count :meth:`put` and successful :meth:`get`."""

    def __init__(self, capacity=4):
        self.capacity = capacity
        self._entries = OrderedDict()  # key -> (fingerprint, localizer)
        self.builds = 0
        self.hits = 0

    def get(self, key, digest):
        """The localizer stored for ``key`` if it was built for ``digest``, else ``None``."""
        entry = self._entries.get(key)
        if entry is None or entry[0] != digest:
            return None
        self._entries.move_to_end(key)
        self.hits += 1
        return entry[1]

    def put(self, key, digest, localizer):
        """Keep ``localizer`` for ``key`` (replacing what ``key`` had)."""
        self._entries.pop(key, None)
        self._entries[key] = (digest, localizer)
        self.builds += 1
        while len(self._entries) > self.capacity:
            self._entries.popitem(last=False)

    def clear(self):
        self._entries.clear()

    def __len__(self):
        return len(self._entries)


#: The add-on's cache (cleared when a file is loaded and when the add-on is disabled); room
#: for the candidates of a search over several objects.
CACHE = LocalizerCache(capacity=8)
