"""Work ahead of a consumer on a thread of its own: a video's frames decoded while the previous one is
warped (PyAV and NumPy release the GIL)."""

from __future__ import annotations


def ahead(items, depth: int):
    """The items of the iterator ``items``, produced on a thread up to ``depth`` ahead of the consumer; an
    error there is raised here, in order; closing this generator early stops the thread."""
    import queue
    import threading

    q: queue.Queue = queue.Queue(maxsize=max(1, depth))
    stop = threading.Event()
    end = object()

    def produce():
        try:
            for item in items:
                while not stop.is_set():
                    try:
                        q.put((item, None), timeout=0.1)
                        break
                    except queue.Full:
                        continue
                if stop.is_set():
                    return
            q.put((end, None))
        except BaseException as exc:  # handed to the consumer
            q.put((end, exc))
        finally:
            close = getattr(items, "close", None)
            if close is not None:
                close()

    worker = threading.Thread(target=produce, daemon=True, name="lenslab-decode")
    worker.start()
    try:
        while True:
            item, exc = q.get()
            if exc is not None:
                raise exc
            if item is end:
                return
            yield item
    finally:
        stop.set()
        while worker.is_alive():  # unblock a producer waiting on a full queue
            try:
                q.get_nowait()
            except queue.Empty:
                worker.join(0.05)


__all__ = ["ahead"]
