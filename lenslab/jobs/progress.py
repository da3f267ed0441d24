"""A progress bar over one image's work (the bands of a warp, the rows of an ST map) that has its total from the
moment it appears, shown only once the work has lasted longer than a second, and says what the command is doing
when a step takes longer than that (reading a large file, making the map)."""

from __future__ import annotations

import sys
import threading
import time

PATIENCE = 1.0  # seconds work may take before the bar appears, and a step before the bar (or a line) says what it is


class RowBar:
    """``progress(rows)`` for :func:`lenslab.warp.warp`: nothing is shown until :meth:`start` gives the total
    (or a step outlasts :data:`PATIENCE`, when one line names it); then a bar of ``total`` rows, or of ``total``
    bands (one a call, whatever rows it gives), that appears once the work has lasted :data:`PATIENCE`."""

    def __init__(self, desc: str, stream=None):
        self.desc = desc
        self.stream = stream or sys.stderr
        self.bar = None
        self.calls = False  # each call is one band (else it gives its rows)
        self.step = "reading"
        self.lock = threading.Lock()
        self.timer = None
        self.closed = False
        self._arm()

    def _arm(self) -> None:
        self._cancel()
        self.timer = threading.Timer(PATIENCE, self._say)
        self.timer.daemon = True
        self.timer.start()

    def _cancel(self) -> None:
        if self.timer is not None:
            self.timer.cancel()
            self.timer = None

    def _say(self) -> None:
        with self.lock:
            if self.closed:  # the timer fired as the bar closed (Ctrl-C): nothing after the command's last line
                return
            if self.bar is None:
                print(f"{self.desc}: {self.step}...", file=self.stream, flush=True)
            elif self.bar.n == 0 or self.bar.n >= self.bar.total:  # before the first band, or after the last (writing)
                self.bar.set_postfix_str(self.step, refresh=True)

    def status(self, step: str) -> None:
        """Name the step now under way (shown if it takes longer than :data:`PATIENCE`)."""
        with self.lock:
            self.step = step
        self._arm()

    def start(self, total: int, unit: str = "row") -> None:
        """The work of ``total`` rows (``unit`` "band": of ``total`` bands, one a call) begins: the bar has its total,
        and appears with it once the work has lasted :data:`PATIENCE` (at once where a step is named)."""
        from tqdm import tqdm

        with self.lock:
            self.bar = tqdm(total=total, unit=unit, file=self.stream, leave=False, desc=self.desc, delay=PATIENCE)
            self.calls = unit == "band"
            self.step = "making the map"
        self._arm()

    def __call__(self, rows: int) -> None:
        with self.lock:
            if self.bar is not None:
                if self.bar.n == 0 and self.bar.postfix:
                    self.bar.set_postfix_str("", refresh=False)
                self.bar.update(1 if self.calls else rows)
                if self.bar.n >= self.bar.total and time.time() - self.bar.start_t >= PATIENCE:
                    self.bar.refresh()  # the last frame, whole (tqdm draws at most every 0.1 s)
        self._cancel()

    def close(self) -> None:
        self._cancel()
        with self.lock:
            self.closed = True
            if self.bar is not None:
                self.bar.close()
