"""A progress bar over one image's output rows that has its total from the moment it appears, and says
what the command is doing when a step takes longer than a second (reading a large file, making the map)."""

from __future__ import annotations

import sys
import threading

PATIENCE = 1.0  # seconds a step may take before the bar (or a line) says what it is doing


class RowBar:
    """``progress(rows)`` for :func:`lenslab.warp.warp`: nothing is shown until :meth:`start` gives the total
    (or a step outlasts :data:`PATIENCE`, when one line names it); then a bar of ``total`` rows."""

    def __init__(self, desc: str, stream=None):
        self.desc = desc
        self.stream = stream or sys.stderr
        self.bar = None
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
            elif self.bar.n == 0:
                self.bar.set_postfix_str(self.step, refresh=True)

    def status(self, step: str) -> None:
        """Name the step now under way (shown if it takes longer than :data:`PATIENCE`)."""
        with self.lock:
            self.step = step
        self._arm()

    def start(self, total: int) -> None:
        """The work of ``total`` rows begins: the bar appears with its total."""
        from tqdm import tqdm

        with self.lock:
            self.bar = tqdm(total=total, unit="row", file=self.stream, leave=False, desc=self.desc)
            self.step = "making the map"
        self._arm()

    def __call__(self, rows: int) -> None:
        with self.lock:
            if self.bar is not None:
                if self.bar.n == 0 and self.bar.postfix:
                    self.bar.set_postfix_str("", refresh=False)
                self.bar.update(rows)
        self._cancel()

    def close(self) -> None:
        self._cancel()
        with self.lock:
            self.closed = True
            if self.bar is not None:
                self.bar.close()
