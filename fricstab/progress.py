"""Progress on stderr that also reaches a log: bars, heartbeats and the first-run compile note.

No command is silent for more than ~10 s (issue 32), on a terminal or with
stderr redirected to a file:

* :func:`bar` is tqdm's bar on a terminal; when stderr is not a terminal (a
  batch job, a log) it is a :class:`LineBar`, one plain line every
  :data:`INTERVAL` seconds (``fricstab: ramp 120/400 (30 %), 14 s``) from a
  daemon thread, so a step that takes long (the first one compiles the
  kernels) still shows the clock.
* :func:`heartbeat` is for a long step with no bar (numba compilation, a
  factorization, an analysis whose bar shows only on a terminal): a line
  ``fricstab: <what> ... 10 s`` every :data:`INTERVAL` seconds until it ends.
* :func:`watchdog`, started by the command line, is the net under both: when
  stderr is not a terminal and nothing was said for :data:`INTERVAL` seconds
  (interpreter start-up, writing figures, a step no bar covers) it prints
  ``fricstab: <activity> ... 65 s``, the activity being the innermost bar or
  heartbeat, else the command.
* :func:`compile_note` says once, before the work, that the numba kernels a
  command needs are not in numba's on-disk cache yet and how long compiling
  them took on the project's machine (:data:`COMPILE_SECONDS`).

``--no-progress`` and ``--quiet`` silence all three (``enabled=False``).
"""

import sys
import threading
import time
from contextlib import contextmanager

__all__ = ["COMPILE_SECONDS", "INTERVAL", "LineBar", "bar", "cache_cold", "compile_note",
           "for_command", "heartbeat", "watchdog"]

#: Seconds between two lines in a log: half the issue's 10 s bound, the other
#: half a margin for a loaded machine.
INTERVAL = 5.0

#: Cold-cache compile time of each group of kernels, seconds of wall time on the
#: project's idle 2-core machine (README: chain ramp 15 s, chain dynamics 96 s of
#: which the contact laws 15, the packing 69 of which the laws ~15); several
#: times that on a loaded one.
COMPILE_SECONDS = {"contact laws": 15, "chain dynamics": 80, "packing": 55}
#: The jitted functions (module, name) that a run of the group calls from
#: Python; their cached machine code holds what they call.
ENTRY = {
    "contact laws": (("fricstab.engine.passes", "eval_pass"),),
    "chain dynamics": (("fricstab.engine.verlet", "_loop"),),
    "packing": (("fricstab.engine.fire", "_fire"),),
}


def _stream(stream):
    return sys.stderr if stream is None else stream


def _isatty(stream):
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False


#: When a progress line was last said (time.monotonic), and what is running now
#: (a stack: the innermost bar or heartbeat last), for :func:`watchdog`.
_LAST = [time.monotonic()]
_ACTIVITY = ["running"]
_LOCK = threading.Lock()   # one line at a time from the threads


def _say(stream, text):
    try:
        with _LOCK:
            _LAST[0] = time.monotonic()
            stream.write(f"fricstab: {text}\n")
            stream.flush()
    except (OSError, ValueError):   # stderr closed: progress is not worth an error
        pass


def _undo(what):
    """Take ``what`` off the activity stack (its last entry; never the command's label)."""
    for i in range(len(_ACTIVITY) - 1, 0, -1):
        if _ACTIVITY[i] == what:
            del _ACTIVITY[i]
            return


@contextmanager
def _doing(what):
    _ACTIVITY.append(what)
    try:
        yield
    finally:
        _undo(what)


def watchdog(enabled=True, label="running", interval=INTERVAL, stream=None):
    """Start the net under the bars (module doc) when ``enabled`` and ``stream`` (stderr)
    is not a terminal: a line after ``interval`` + 1 s without one (6 s: within the
    issue's 10 s).  Returns a function that stops it (idempotent)."""
    stream = _stream(stream)
    if not enabled or _isatty(stream):
        return lambda: None
    _ACTIVITY[0] = label
    _LAST[0] = start = time.monotonic()

    def tick(_):   # 1 s after a bar's or heartbeat's line would have come: no doubles
        now = time.monotonic()
        if now - _LAST[0] >= interval + 1.0:
            _say(stream, f"{_ACTIVITY[-1]} ... {now - start:.0f} s")

    return _Ticker(tick, min(interval, 1.0) / 2).stop


class _Ticker:
    """A daemon thread that calls ``tick(elapsed)`` every ``interval`` s until :meth:`stop`."""

    def __init__(self, tick, interval):
        self._tick, self._interval = tick, interval
        self._done = threading.Event()
        self.start = time.monotonic()
        self._thread = threading.Thread(target=self._run, daemon=True, name="fricstab-progress")
        self._thread.start()

    def _run(self):
        while not self._done.wait(self._interval):
            self._tick(time.monotonic() - self.start)

    def stop(self):
        self._done.set()
        if self._thread is not threading.current_thread():
            self._thread.join()
        return time.monotonic() - self.start


@contextmanager
def for_command(argv):
    """:func:`watchdog` over a run of ``main(argv)``: on for a real command line
    (``argv`` None: ``sys.argv``) without ``--quiet`` or ``--no-progress``; off for
    ``main([...])`` called from Python (tests that read stderr)."""
    words = sys.argv[1:] if argv is None else []
    on = bool(words) and not {"--quiet", "--no-progress"} & set(words)
    stop = watchdog(on, label=" ".join(w for w in words[:2] if not w.startswith("-")) or "running")
    try:
        yield
    finally:
        stop()


class LineBar:
    """The tqdm subset the protocols use (``update``, ``set_postfix_str``, iteration,
    ``close``, a context manager), printing a line every ``interval`` s instead of a bar."""

    def __init__(self, iterable=None, total=None, desc="", unit="it", initial=0,
                 interval=INTERVAL, stream=None, **_):
        self.iterable, self.desc, self.unit = iterable, desc, unit
        if total is None and iterable is not None and hasattr(iterable, "__len__"):
            total = len(iterable)
        self.total, self.n, self.postfix = total, initial, ""
        self._stream = _stream(stream)
        self._closed = False
        self._label = desc
        _ACTIVITY.append(desc)
        self._ticker = _Ticker(self._line, interval)

    def status(self, elapsed):
        """``ramp 120/400 (30 %), 14 s`` (no total: ``ramp 120 step, 14 s``)."""
        if self.total:
            done = f"{self.n}/{self.total} ({100 * self.n / self.total:.0f} %)"
        else:
            done = f"{self.n} {self.unit}"
        post = f" [{self.postfix}]" if self.postfix else ""
        return f"{self.desc} {done}{post}, {elapsed:.0f} s".strip()

    def _line(self, elapsed):
        _say(self._stream, self.status(elapsed))

    def update(self, n=1):
        self.n += n

    def set_postfix_str(self, s="", refresh=True):
        self.postfix = str(s)

    def set_description(self, desc=None, refresh=True):
        self.desc = desc or ""

    def refresh(self):
        pass

    def close(self):
        if not self._closed:
            self._closed = True
            self._line(self._ticker.stop())
            _undo(self._label)

    def __iter__(self):
        try:
            for item in self.iterable:
                yield item
                self.n += 1
        finally:
            self.close()

    def __len__(self):
        return self.total or 0

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def bar(iterable=None, total=None, desc="", unit="it", enabled=True, stream=None, **kw):
    """A progress bar on ``stream`` (stderr): tqdm's on a terminal, a :class:`LineBar`
    in a log, tqdm's disabled one when ``enabled`` is false (--no-progress, --quiet).

    ``kw`` goes to tqdm (``initial``, ``unit_scale``, ...)."""
    from tqdm import tqdm
    stream = _stream(stream)
    if enabled and not _isatty(stream):
        return LineBar(iterable, total=total, desc=desc, unit=unit, stream=stream,
                       initial=kw.get("initial", 0), interval=kw.pop("interval", INTERVAL))
    kw.pop("interval", None)
    return tqdm(iterable, total=total, desc=desc, unit=unit, disable=not enabled, file=stream,
                **kw)


@contextmanager
def heartbeat(what, enabled=True, interval=INTERVAL, stream=None):
    """Within the block, ``fricstab: <what> ... 10 s`` every ``interval`` s on ``stream``.

    On a terminal the line is rewritten in place (and ended when the block
    ends); in a log it is a new line each time.  Nothing when not ``enabled``.
    """
    stream = _stream(stream)
    if not enabled:
        yield
        return
    tty = _isatty(stream)
    printed = []

    def tick(elapsed):
        printed.append(elapsed)
        if tty:
            try:
                stream.write(f"\rfricstab: {what} ... {elapsed:.0f} s")
                stream.flush()
            except (OSError, ValueError):
                pass
        else:
            _say(stream, f"{what} ... {elapsed:.0f} s")

    ticker = _Ticker(tick, interval)
    try:
        with _doing(what):
            yield
    finally:
        ticker.stop()
        if tty and printed:
            try:
                stream.write("\n")
            except (OSError, ValueError):
                pass


def _dispatcher(module, name):
    import importlib
    return getattr(importlib.import_module(module), name, None)


def cache_cold(group):
    """True when an entry kernel of ``group`` (a key of :data:`ENTRY`) has no index in
    numba's on-disk cache (``__pycache__`` beside its source, or ``NUMBA_CACHE_DIR``):
    it will be compiled.  An index found does not prove every signature is cached."""
    import os
    for module, name in ENTRY[group]:
        fn = _dispatcher(module, name)
        cache = getattr(fn, "_cache", None)
        index = getattr(getattr(cache, "_cache_file", None), "_index_path", None)
        if index is not None and not os.path.exists(index):
            return True
    return False


def compile_note(groups, enabled=True, stream=None):
    """Say once that the kernels of ``groups`` are compiled now (a cold cache), with the
    time that took on the project's machine; returns whether any group was cold."""
    cold = [g for g in groups if cache_cold(g)]
    if cold and enabled:
        seconds = sum(COMPILE_SECONDS[g] for g in cold)
        _say(_stream(stream), f"compiling numba kernels ({', '.join(cold)}; first run only, "
                              f"about {seconds} s on an idle 2-core machine; `fricstab "
                              "warmup` compiles them all)")
    return bool(cold)
