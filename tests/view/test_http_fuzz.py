"""A bounded fuzz test of hunav_view's HTTP API (issue 31): seeded random requests from four threads
at once (a few seconds), mixing valid editor requests with hostile ones: bytes that are not UTF-8
in paths, parameters and bodies, JSON nested thousands deep, random and mutated documents, saves of
several files at once, requests from another Origin or for another Host, POSTs without or with a
wrong token or as text/plain. Properties checked:
  - the server lives, and every answer of the API is JSON with a status below 500;
  - a request that is not the page's (Origin, Host, token, content type) never writes a file;
  - every file in the editor's folder is one the test put there or one an admitted save named, each
    holding the document of one of its saves (never another file's), and nothing appears outside
    the folder; no temporary file is left.
HUNAV_FUZZ_SEED picks another seed, HUNAV_FUZZ_REQUESTS another count (default 600)."""
import json
import os
import random
import shutil
import socket
import sys
import tempfile
import threading
import time
import urllib.parse

from viewproc import View

API_GETS = ["/api/info", "/api/scene", "/api/frame", "/api/stream", "/api/replay", "/api/editor/files",
            "/api/editor/open", "/api/editor/replay", "/api/replay/chunk", "/api/editor/replay/chunk",
            "/api/nothing", "/", "/app.js", "/favicon.ico"]
API_POSTS = ["/api/editor/validate", "/api/editor/save", "/api/editor/run", "/api/info", "/api/editor/nothing"]


def random_text(rng, n):
    """Bytes of every kind: ASCII, valid UTF-8, invalid sequences, NUL, path separators, dots."""
    pieces = [b"a", b"Z", b"0", b".", b"..", b"/", b"\\", b"\x00", b"\xff", b"\xc0\xaf", b"\xed\xa0\x80", b"\xe2\x82",
              "é".encode(), "😀".encode(), b"%", b"?", b"#", b" ", b"yaml", b".yaml", b"view_runs"]
    return b"".join(rng.choice(pieces) for _ in range(n))


def random_json(rng, depth):
    kind = rng.randrange(7 if depth < 6 else 4)
    if kind == 0:
        return rng.choice([None, True, False])
    if kind == 1:
        return rng.choice([0, -1, 1e308, -1e-300, 3.5, 2 ** 63, rng.uniform(-1e6, 1e6)])
    if kind == 2 or kind == 3:
        return random_text(rng, rng.randrange(6)).decode("utf-8", "replace")
    if kind == 4:
        return [random_json(rng, depth + 1) for _ in range(rng.randrange(4))]
    if kind == 5:
        return {"__map": [[random_text(rng, 3).decode("utf-8", "replace"), random_json(rng, depth + 1)]
                          for _ in range(rng.randrange(4))]}
    return {random_text(rng, 3).decode("utf-8", "replace"): random_json(rng, depth + 1)
            for _ in range(rng.randrange(3))}


def mutate_doc(rng, doc):
    """The scenario's document with a few values replaced (a valid scenario, often)."""
    d = json.loads(json.dumps(doc))
    for _ in range(rng.randrange(3)):
        kv = rng.choice(d["__map"])
        if rng.random() < 0.5 and not isinstance(kv[1], (dict, list)):
            kv[1] = rng.choice(["0.02", "-1", "x", "1e400", "", "200"])
    return d


class Fuzzer:
    def __init__(self, view, root, doc):
        self.view, self.root, self.doc = view, root, doc
        self.port = urllib.parse.urlparse(view.url).port
        self.token = view.token()
        self.lock = threading.Lock()
        self.problems = []
        self.written = {}  # path -> the YAML names of the documents admitted saves wrote there
        self.counts = {}

    def count(self, what):
        with self.lock:
            self.counts[what] = self.counts.get(what, 0) + 1

    def problem(self, text):
        with self.lock:
            self.problems.append(text)

    def raw(self, method, target, headers, body):
        """One request over a socket of its own (bytes as given): (status, body text) or None."""
        head = [b"%s %s HTTP/1.1" % (method.encode(), target)]
        for k, v in headers.items():
            head.append(k.encode() + b": " + (v if isinstance(v, bytes) else v.encode()))
        if body is not None:
            head.append(b"Content-Length: %d" % len(body))
        head.append(b"Connection: close")
        data = b"\r\n".join(head) + b"\r\n\r\n" + (body or b"")
        with socket.create_connection(("127.0.0.1", self.port), timeout=30) as s:
            s.sendall(data)
            reply = b""
            while True:
                chunk = s.recv(65536)
                if not chunk:
                    break
                reply += chunk
                if target.startswith(b"/api/stream") and len(reply) > 0:
                    break  # an event stream does not end by itself
        if not reply:
            return None
        head, _, text = reply.partition(b"\r\n\r\n")
        try:
            status = int(head.split(b" ")[1])
        except (IndexError, ValueError):
            return None
        return status, text.decode("utf-8", "replace")

    def one(self, rng):
        post = rng.random() < 0.6
        if post and rng.random() < 0.2:
            method = rng.choice(["POST", "POST", "PUT", "DELETE"])
        else:
            method = "POST" if post else "GET"
        path = rng.choice(API_POSTS if post else API_GETS)
        query = b""
        if not post and rng.random() < 0.7:
            value = rng.choice([b"passing.yaml", b"..%2Fx", b"%FF", b"view_runs", urllib.parse.quote_from_bytes(
                random_text(rng, rng.randrange(1, 8))).encode()])
            query = b"?path=" + value
        # Who sends it: the page (its host, origin, token, JSON), or someone else in one respect.
        headers = {"Host": "127.0.0.1:%d" % self.port}
        page = True
        tamper = rng.random()
        if tamper < 0.12:
            headers["Host"] = rng.choice(["evil.example", "127.0.0.1:1", "localhost", "",
                                          "127.0.0.1:%d.evil" % self.port])
            page = False
        elif tamper < 0.24:
            headers["Origin"] = rng.choice(["http://evil.example", "null", "https://127.0.0.1:%d" % self.port,
                                            "http://127.0.0.1:%d.evil.example" % self.port])
            page = False
        elif tamper < 0.30:
            headers["Origin"] = "http://127.0.0.1:%d" % self.port
        body = None
        if method != "GET":
            headers["Content-Type"] = "application/json"
            if rng.random() < 0.12:
                headers["Content-Type"] = rng.choice(["text/plain", "application/x-www-form-urlencoded", ""])
                page = False
            token = self.token
            if rng.random() < 0.12:
                token = rng.choice(["", "0" * 32, self.token[:-1], self.token + "0"])
                page = False
            if token:
                headers["X-HuNav-Token"] = token
            body, target_file = self.body(rng)
        else:
            target_file = None
        reply = self.raw(method, path.encode() + query, headers, body)
        if reply is None:
            self.problem("no answer to %s %s" % (method, path))
            return
        status, text = reply
        self.count(status)
        if path.startswith("/api/") and path != "/api/stream":
            try:
                answer = json.loads(text)
            except ValueError:
                self.problem("%s %s: an answer that is not JSON: %d %r" % (method, path, status, text[:200]))
                return
        if status >= 500:
            self.problem("%s %s%s: status %d %s" % (method, path, query[:60], status, text[:300]))
        if not page and path.startswith("/api/editor") and method != "GET" and status == 200:
            self.problem("a request that is not the page's was served: %s %s %s" % (method, path, headers))
        if page and method == "POST" and path == "/api/editor/save" and status == 200 and answer.get("ok"):
            with self.lock:
                self.written.setdefault(answer["path"], set()).add(target_file)

    def body(self, rng):
        """A body and, for a document to save, the name: it carries (to tell whose document a file holds)."""
        kind = rng.random()
        if kind < 0.08:
            depth = rng.choice([300, 5000, 200000])
            return b"[" * depth + b"]" * depth, None
        if kind < 0.16:
            return random_text(rng, rng.randrange(1, 40)), None
        if kind < 0.26:
            return json.dumps(random_json(rng, 0)).encode(), None
        if kind < 0.32:
            return b'{"path": "\xff.yaml", "doc": {}}', None
        path = rng.choice(["a.yaml", "b.yaml", "c.yml", "sub/d.yaml", ".", "", "sub", "../x.yaml", "notes.txt",
                           "view_runs/e.yaml", "passing.yaml"])
        doc = mutate_doc(rng, self.doc)
        name = "fuzz%d" % rng.randrange(10 ** 9)
        for kv in doc["__map"]:
            if kv[0] == "name":
                kv[1] = name
        request = {"path": path, "doc": doc}
        if rng.random() < 0.1:
            request["planner"] = rng.choice(["dwb", "none", "../../x", "nonesuch", 3])
            request["duration"] = rng.choice([0.2, -1, "x", None])
        return json.dumps(request).encode(), name


def main():
    seed = int(os.environ.get("HUNAV_FUZZ_SEED", "31"))
    total = int(os.environ.get("HUNAV_FUZZ_REQUESTS", "600"))
    work = tempfile.mkdtemp(prefix="hunav_view_fuzz.")
    root = os.path.join(work, "root")
    os.makedirs(os.path.join(root, "sub"))
    shutil.copy(os.path.join(os.environ["REPO"], "scenarios", "passing.yaml"), root)
    before = {"passing.yaml"}
    view = View(["--no-live", "--editor", root])
    problems = []
    try:
        doc = json.loads(view.request("/api/editor/open?path=passing.yaml")[1])["doc"]
        fuzzer = Fuzzer(view, root, doc)
        started = time.time()
        deadline = started + 120  # a bound on a loaded machine; a quiet one takes a few seconds

        def worker(k):
            rng = random.Random(seed * 1000 + k)
            for _ in range(total // 4):
                if time.time() > deadline:
                    fuzzer.problem("the fuzz did not finish within 120 s")
                    return
                try:
                    fuzzer.one(rng)
                except (OSError, socket.timeout) as e:
                    fuzzer.problem("thread %d: %s" % (k, e))
                    return
        threads = [threading.Thread(target=worker, args=(k,)) for k in range(4)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        print("%d requests in %.1f s (seed %d), statuses %s"
              % (total, time.time() - started, seed, sorted(fuzzer.counts.items())))
        problems += fuzzer.problems
        if not view.alive():
            problems.append("hunav_view died")
        # What is in the folder: the test's files, and files admitted saves named, each holding one
        # of the documents saved under its name.
        for d, _, files in os.walk(root):
            for f in files:
                rel = os.path.relpath(os.path.join(d, f), root)
                if f.startswith(".hunav_view_"):
                    problems.append("a temporary file is left: " + rel)
                elif rel.startswith("view_runs" + os.sep):
                    continue  # a run's results
                elif rel not in before and rel not in fuzzer.written:
                    problems.append("a file no admitted save named: " + rel)
                elif rel in fuzzer.written:
                    with open(os.path.join(d, f)) as fh:
                        text = fh.read()
                    names = [n for n in fuzzer.written[rel] if n and ("name: %s\n" % n) in text]
                    if not names:
                        problems.append("%s holds none of the documents saved to it" % rel)
        if sorted(os.listdir(work)) != ["root"]:
            problems.append("files outside the editor's folder: %s" % sorted(os.listdir(work)))
    finally:
        code = view.stop()
        shutil.rmtree(work, ignore_errors=True)
    if code not in (0, -15):
        problems.append("hunav_view exited with %s after SIGTERM" % code)
    for p in problems[:40]:
        print("FAIL:", p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
