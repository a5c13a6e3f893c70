"""LCM in Python, with upstream LCM's API (lcm-python), over Debian's liblcm.

Debian bookworm packages LCM's C, C++ and Java libraries but not its Python binding; this package
gives Debian's Python the same API, so LCM Python programs run unchanged::

    import lcm
    lc = lcm.LCM()                       # $LCM_DEFAULT_URL, else LCM's default URL
    sub = lc.subscribe("CHANNEL", lambda channel, data: print(channel, len(data)))
    sub.set_queue_capacity(1000)
    lc.publish("CHANNEL", b"bytes")
    lc.handle_timeout(100)               # 1: a message was dispatched, 0: timeout
    lc.unsubscribe(sub)

    for event in lcm.EventLog("run.lcmlog", "r"):
        print(event.timestamp, event.channel, len(event.data))

python/README.md, "LCM in Python".
"""
import os

from lcm import _lcm
from lcm._lcm import LCM, LCMSubscription

__all__ = ["LCM", "LCMSubscription", "Event", "EventLog"]


class Event:
    """One event of an LCM log: its number, time stamp (microseconds since the epoch, as the logger
    received it), channel and the message's bytes."""

    def __init__(self, eventnum, timestamp, channel, data):
        self.eventnum = eventnum
        self.timestamp = timestamp
        self.channel = channel
        self.data = data

    def __repr__(self):
        return (f"Event(eventnum={self.eventnum}, timestamp={self.timestamp}, channel={self.channel!r}, "
                f"data=<{len(self.data)} bytes>)")


class EventLog:
    """An LCM log file opened for reading ('r', iterable over its events) or writing ('w').

    Writing to an existing file needs overwrite=True (a ValueError otherwise), as upstream."""

    def __init__(self, path, mode="r", overwrite=False):
        if mode not in ("r", "w"):
            raise ValueError("invalid event log mode (expected 'r' or 'w')")
        path = os.fspath(path)
        if mode == "w" and os.path.exists(path) and not overwrite:
            raise ValueError(f"Refusing to overwrite existing log file {path} unless overwrite is set to True")
        self.mode = mode
        self.c_eventlog = _lcm.EventLog(path, mode)

    def close(self):
        """Closes the file; further calls raise ValueError."""
        self.c_eventlog.close()

    def read_next_event(self):
        """The next Event, or None at the end of the log."""
        raw = self.c_eventlog.read_next_event()
        return None if raw is None else Event(*raw)

    def seek(self, filepos):
        """Moves to byte offset filepos (an offset tell() returned)."""
        self.c_eventlog.seek(filepos)

    def seek_to_timestamp(self, timestamp):
        """Moves to the first event at or after `timestamp` (microseconds)."""
        self.c_eventlog.seek_to_timestamp(timestamp)

    def size(self):
        """The file's size in bytes."""
        return self.c_eventlog.size()

    def tell(self):
        """The byte offset of the next event."""
        return self.c_eventlog.tell()

    def write_event(self, utime, channel, data):
        """Appends an event (utime: microseconds) with the message's bytes."""
        self.c_eventlog.write_event(utime, channel, data)

    def __iter__(self):
        if self.mode != "r":
            raise ValueError("an event log open for writing cannot be iterated")
        return self

    def __next__(self):
        event = self.read_next_event()
        if event is None:
            raise StopIteration
        return event

    next = __next__

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
