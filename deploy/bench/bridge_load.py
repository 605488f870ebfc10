#!/usr/bin/env python3
"""The client of deploy/bench/bridge_load.sh: how fast a bridge answers while other clients hold
connections open.

    bridge_load.py PORT CASE...

A CASE is `streams=S,half_open=H[,trickle=T][,from=ADDR]` (any count may be 0): S clients keep
an event stream (/api/events) open, reading it, and open it again a second after the bridge
refuses or closes it (what a browser's EventSource does); H connections are kept half-open: a
request line and one header, never finished, opened again as soon as the bridge drops one (what a
hostile or broken client does); T more connections trickle a header that never ends, a byte every
half second. The held connections come from ADDR (default 127.0.0.1, the measuring client's own
address; 127.0.0.2 is another host's as far as the bridge can tell). While they are held, 200
fresh clients ask GET /metrics and 200 GET /api/state, one at a time (Prometheus opens a
connection per scrape), each with a 10 s limit (fewer when they take more than 30 s in all). Per
case, one line of JSON: the latencies' p50, p99 and max in ms, the requests that failed (no
answer within 10 s, or not 200), the streams open at the end and the 503s the stream clients got.

Standard library only; every connection to 127.0.0.1.
"""

import json
import selectors
import socket
import statistics
import sys
import threading
import time

HOST = "127.0.0.1"
LIMIT = 10.0  # s: a Prometheus scrape's default timeout
REQUESTS = 200  # per endpoint and case
BUDGET = 30.0  # s per endpoint and case: fewer requests when they are slow
SETTLE = 2.0  # s: the held connections are opened before measuring


class Holders(threading.Thread):
    """Keeps `streams` event streams and `half_open` unfinished requests open, on one selector."""

    def __init__(self, port, streams, half_open, trickle, source):
        super().__init__(daemon=True)
        self.port, self.want_streams, self.want_half, self.want_trickle = port, streams, half_open, trickle
        self.source = source
        self.sel = selectors.DefaultSelector()
        self.stop = threading.Event()
        self.open_streams = 0
        self.refused = 0  # 503 answers to a stream request
        self.reopen_at = []  # times at which a refused stream client tries again

    def connect(self, kind):
        s = socket.socket()
        s.setblocking(False)
        try:
            s.bind((self.source, 0))
            s.connect_ex((HOST, self.port))
        except OSError:
            s.close()
            return False
        request = {"stream": b"GET /api/events HTTP/1.1\r\nHost: bench\r\nAccept: text/event-stream\r\n\r\n",
                   "half": b"GET /api/state HTTP/1.1\r\nHost: bench\r\n",
                   "trickle": b"GET /api/state HTTP/1.1\r\nX-Slow: "}[kind]
        self.sel.register(s, selectors.EVENT_WRITE, {"kind": kind, "request": request, "seen": b"", "ok": False})
        return True

    def close(self, key):
        self.sel.unregister(key.fileobj)
        key.fileobj.close()
        data = key.data
        if data["kind"] == "stream":
            if data["ok"]:
                self.open_streams -= 1
            self.reopen_at.append(time.monotonic() + 1.0)
        else:
            self.connect(data["kind"])  # at once

    def trickle(self):
        for key in list(self.sel.get_map().values()):
            if key.data["kind"] == "trickle" and key.events == selectors.EVENT_READ:
                try:
                    key.fileobj.send(b"a")
                except OSError:
                    self.close(key)

    def run(self):
        for _ in range(self.want_half):
            self.connect("half")
        for _ in range(self.want_trickle):
            self.connect("trickle")
        next_trickle = time.monotonic() + 0.5
        for _ in range(self.want_streams):
            self.connect("stream")
        while not self.stop.is_set():
            now = time.monotonic()
            due = [t for t in self.reopen_at if t <= now]
            self.reopen_at = [t for t in self.reopen_at if t > now]
            for _ in due:
                self.connect("stream")
            if now >= next_trickle:
                next_trickle = now + 0.5
                self.trickle()
            for key, events in self.sel.select(timeout=0.1):
                data = key.data
                if events & selectors.EVENT_WRITE:
                    try:
                        key.fileobj.send(data["request"])
                    except OSError:
                        self.close(key)
                        continue
                    self.sel.modify(key.fileobj, selectors.EVENT_READ, data)
                    continue
                try:
                    chunk = key.fileobj.recv(65536)
                except OSError:
                    chunk = b""
                if not chunk:
                    self.close(key)
                    continue
                if data["kind"] == "stream" and not data["ok"] and len(data["seen"]) < 64:
                    data["seen"] += chunk
                    if data["seen"].startswith(b"HTTP/1.1 200"):
                        data["ok"] = True
                        self.open_streams += 1
                    elif data["seen"].startswith(b"HTTP/1.1 503"):
                        self.refused += 1
        for key in list(self.sel.get_map().values()):
            key.fileobj.close()


def timed_get(port, path):
    """Seconds until a complete 200 answer on a fresh connection, or None."""
    start = time.monotonic()
    try:
        with socket.create_connection((HOST, port), timeout=LIMIT) as s:
            s.settimeout(max(0.001, LIMIT - (time.monotonic() - start)))
            s.sendall(f"GET {path} HTTP/1.1\r\nHost: bench\r\nConnection: close\r\n\r\n".encode())
            answer = b""
            while True:
                chunk = s.recv(65536)
                if not chunk:
                    break
                answer += chunk
                if time.monotonic() - start > LIMIT:
                    return None
    except OSError:
        return None
    if not answer.startswith(b"HTTP/1.1 200"):
        return None
    return time.monotonic() - start


def percentile(values, p):
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(p / 100.0 * (len(ordered) - 1))))]


def measure(port, streams, half_open, trickle, source):
    holders = Holders(port, streams, half_open, trickle, source)
    holders.start()
    time.sleep(SETTLE)
    row = {"streams": streams, "half_open": half_open, "trickle": trickle, "from": source}
    for path in ("/metrics", "/api/state"):
        times, failed = [], 0
        budget = time.monotonic() + BUDGET
        for _ in range(REQUESTS):
            if time.monotonic() > budget:
                break
            t = timed_get(port, path)
            if t is None:
                failed += 1
            else:
                times.append(t * 1000.0)
        name = path.strip("/").replace("api/", "")
        row[name] = {"p50_ms": round(statistics.median(times), 1) if times else None,
                     "p99_ms": round(percentile(times, 99), 1) if times else None,
                     "max_ms": round(max(times), 1) if times else None, "failed": failed,
                     "requests": len(times) + failed}
    row["streams_open"] = holders.open_streams
    row["stream_503s"] = holders.refused
    holders.stop.set()
    holders.join()
    time.sleep(0.5)  # let the bridge see the connections go
    return row


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    port = int(sys.argv[1])
    for case in sys.argv[2:]:
        fields = dict(part.split("=") for part in case.split(","))
        print(json.dumps(measure(port, int(fields.get("streams", 0)), int(fields.get("half_open", 0)),
                                 int(fields.get("trickle", 0)), fields.get("from", HOST))), flush=True)


if __name__ == "__main__":
    main()
