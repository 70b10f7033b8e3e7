"""One localization or search run, in the foreground or on a worker thread; free of ``bpy``.

A localization (:class:`LocalizeJob`) has two phases: preparing the full shape
(``dualspectra.Localizer``, skipped when a prepared one is given) and locating the partial
on it (``Localizer.locate``). A search (:class:`SearchJob`) prepares each candidate full shape
that has no prepared one, then ranks them all for the partial (``dualspectra.search``). The
library releases the GIL while it computes, so a Python thread running a job leaves Blender's
interface responsive. The thread only touches the job: the latest progress report, a cancel
flag that the progress callback turns into ``False`` (which makes the library stop and raise
``dualspectra.Cancelled``), and the outcome. The operator's modal timer polls it; nothing
here calls Blender.
"""

import threading
import time

#: Share of the progress bar given to preparing the full shape when it is not reused.
PREPARATION_SHARE = 0.1


class Job:
    """What every run has: progress reports, cancelling, a time limit, a thread, the outcome.

    After :meth:`run` exactly one of ``result``, ``cancelled`` (True) or ``error`` (the
    exception) is set. Subclasses compute in :meth:`_work`, reporting through
    :meth:`_reporter`.
    """

    thread_name = "dualspectra-job"

    def __init__(self, module, on_progress=None, time_limit=None):
        self._module = module
        self._time_limit = time_limit if time_limit else None
        self._on_progress = on_progress
        self._cancel = threading.Event()
        self._done = threading.Event()
        self._lock = threading.Lock()
        self._thread = None
        self._fraction = 0.0
        self._stage = "starting"
        self._reports = 0
        self.started_at = None
        self.finished_at = None
        self.result = None
        self.error = None
        self.cancelled = False
        self.timed_out = False

    # -- progress, called by the library from the running thread --------------------------
    def _reporter(self, lo, hi):
        def report(fraction, stage):
            with self._lock:
                self._fraction = lo + (hi - lo) * min(max(float(fraction), 0.0), 1.0)
                self._stage = str(stage)
                self._reports += 1
                now = self._fraction, self._stage
            if self._on_progress is not None:
                self._on_progress(*now)
            if self._time_limit is not None and time.monotonic() - self.started_at > self._time_limit:
                self.timed_out = True
                self._cancel.set()
            return not self._cancel.is_set()

        return report

    def progress(self):
        """``(fraction in [0, 1], stage name, number of reports so far)``."""
        with self._lock:
            return self._fraction, self._stage, self._reports

    # -- running ------------------------------------------------------------------------------
    def _work(self):
        """Compute and return the result (subclasses)."""
        raise NotImplementedError

    def _release(self):
        """Drop the input arrays once the run ended (subclasses)."""

    def run(self):
        """Run in the calling thread; returns when finished, cancelled or failed."""
        self.started_at = time.monotonic()
        try:
            self.result = self._work()
        except self._module.Cancelled:
            self.cancelled = True
        except BaseException as exc:  # reported to the user by the operator, never lost
            if self._cancel.is_set() and isinstance(exc, KeyboardInterrupt):
                self.cancelled = True
            else:
                self.error = exc
        finally:
            self.finished_at = time.monotonic()
            self._release()
            self._done.set()

    def start(self):
        """Run on a daemon thread and return at once; poll :attr:`done`."""
        if self._thread is not None:
            raise RuntimeError("job already started")
        self._thread = threading.Thread(target=self.run, name=self.thread_name, daemon=True)
        self._thread.start()

    def cancel(self):
        """Ask the run to stop at its next progress report."""
        self._cancel.set()

    @property
    def cancel_requested(self):
        return self._cancel.is_set()

    @property
    def done(self):
        return self._done.is_set()

    def wait(self, timeout=None):
        """Block until finished (or ``timeout`` seconds); returns :attr:`done`."""
        return self._done.wait(timeout)

    @property
    def elapsed(self):
        if self.started_at is None:
            return 0.0
        end = self.finished_at if self.finished_at is not None else time.monotonic()
        return end - self.started_at


class LocalizeJob(Job):
    """Locate ``(partial_vertices, partial_faces)`` on the full shape once.

    ``module`` is the imported ``dualspectra`` package. ``localizer`` is a prepared
    ``module.Localizer`` to reuse, or ``None`` to prepare one from ``full_vertices``,
    ``full_faces`` and ``options`` (then kept in :attr:`localizer`, also when locating
    fails, so that the caller can keep it).

    After the run exactly one of ``result`` (the Localization), ``cancelled`` (True) or
    ``error`` (the exception) is set; :attr:`phase` says which phase ended the run
    (``"full"``: preparing the full shape, ``"partial"``: locating the partial), so that an
    error can name its mesh. ``on_progress(fraction, stage)``, if given, is called after each
    report from the running thread (for a foreground run, to update Blender's progress
    cursor). ``time_limit`` (seconds) cancels the run at the first report after it and sets
    :attr:`timed_out`.
    """

    thread_name = "dualspectra-localize"

    def __init__(self, module, full_vertices, full_faces, partial_vertices, partial_faces, options, localizer=None,
                 on_progress=None, time_limit=None):
        super().__init__(module, on_progress, time_limit)
        self._full = (full_vertices, full_faces)
        self._partial = (partial_vertices, partial_faces)
        self._options = dict(options)
        self.localizer = localizer
        self.reused = localizer is not None
        self.phase = "full"

    def _work(self):
        split = 0.0
        if self.localizer is None:
            split = PREPARATION_SHARE
            self.localizer = self._module.Localizer(*self._full, progress=self._reporter(0.0, split), **self._options)
        self.phase = "partial"
        return self.localizer.locate(*self._partial, progress=self._reporter(split, 1.0))

    def _release(self):
        self._full = self._partial = None  # free the arrays


class SearchJob(Job):
    """Rank candidate full shapes for ``(partial_vertices, partial_faces)``
    (``dualspectra.search``).

    ``fulls`` is a list of ``(vertices, faces, localizer)``: a candidate's world-space mesh
    and its prepared ``module.Localizer`` to reuse, or ``None`` to prepare one with
    ``options``. The prepared shapes end up in :attr:`localizers` (in the order of
    ``fulls``; ``None`` for those not prepared when the run stopped), so that the caller can
    keep them, and :attr:`reused` says which were given.

    The result is the library's list of ``Match`` (best first; ``index`` into ``fulls``).
    :attr:`phase` is ``("full", i)`` while candidate ``i`` is prepared and ``("partial",
    None)`` while searching, so that an error can name its mesh. Preparing takes
    :data:`PREPARATION_SHARE` of the bar per candidate prepared, at most half of it.
    """

    thread_name = "dualspectra-search"

    def __init__(self, module, partial_vertices, partial_faces, fulls, options, on_progress=None, time_limit=None):
        super().__init__(module, on_progress, time_limit)
        self._partial = (partial_vertices, partial_faces)
        self._meshes = [(v, f) for v, f, _ in fulls]
        self._options = dict(options)
        self.localizers = [localizer for _, _, localizer in fulls]
        self.reused = [localizer is not None for localizer in self.localizers]
        self.phase = ("partial", None)

    def _work(self):
        missing = [i for i, localizer in enumerate(self.localizers) if localizer is None]
        share = min(0.5, PREPARATION_SHARE * len(missing))
        for k, i in enumerate(missing):
            self.phase = ("full", i)
            lo, hi = share * k / len(missing), share * (k + 1) / len(missing)
            self.localizers[i] = self._module.Localizer(*self._meshes[i], progress=self._reporter(lo, hi), **self._options)
        self.phase = ("partial", None)
        return self._module.search(self._partial, self.localizers, progress=self._reporter(share, 1.0))

    def _release(self):
        self._partial = self._meshes = None  # free the arrays
