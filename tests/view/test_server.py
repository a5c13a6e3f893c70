"""hunav_view refuses paths out of the editor's folder (.., absolute, symlinks) and malformed
requests with clear errors, and keeps serving."""
import json
import os
import shutil
import socket
import sys
import tempfile
import urllib.error
import urllib.parse
import urllib.request

from viewproc import View


def request(url, body=None, raw=None, method=None):
    data = raw if raw is not None else (json.dumps(body).encode() if body is not None else None)
    req = urllib.request.Request(url, data=data, method=method, headers={"Content-Type": "application/json"})
    try:
        with urllib.request.urlopen(req, timeout=10) as r:
            return r.status, r.read().decode()
    except urllib.error.HTTPError as e:
        return e.code, e.read().decode()


def main():
    work = tempfile.mkdtemp(prefix="hunav_view_server.")
    root = os.path.join(work, "root")
    outside = os.path.join(work, "outside")
    os.makedirs(root)
    os.makedirs(outside)
    shutil.copy(os.path.join(os.environ["REPO"], "scenarios", "passing.yaml"), root)
    with open(os.path.join(outside, "secret.yaml"), "w") as f:
        f.write("name: secret\n")
    os.symlink(outside, os.path.join(root, "out"))
    os.symlink(os.path.join(outside, "secret.yaml"), os.path.join(root, "evil.yaml"))
    view = View(["--no-live", "--editor", root])
    base = view.url
    failures = []

    def expect(what, status, body, want_status, want_text):
        ok = status == want_status and want_text in body
        try:
            json.loads(body)
        except ValueError:
            ok = False
        print("%-55s %d %s" % (what, status, body[:110]))
        if not ok:
            failures.append("%s: got %d %s, want %d with %r" % (what, status, body, want_status, want_text))

    try:
        q = lambda p: base + "/api/editor/open?path=" + urllib.parse.quote(p)
        expect("open a file inside", *request(q("passing.yaml")), 200, '"path":"passing.yaml"')
        expect("open ../", *request(q("../outside/secret.yaml")), 403, "'..' is refused")
        expect("open an absolute path", *request(q(os.path.join(outside, "secret.yaml"))), 403, "absolute paths are refused")
        expect("open a symlinked file out", *request(q("evil.yaml")), 403, "leads out of")
        expect("open through a symlinked folder", *request(q("out/secret.yaml")), 403, "leads out of")
        expect("open a missing file", *request(q("nothing.yaml")), 403, "no such file")
        expect("open without a path", *request(base + "/api/editor/open"), 400, "missing query parameter 'path'")
        doc = json.loads(request(q("passing.yaml"))[1])["doc"]
        for bad in ["../escape.yaml", os.path.join(work, "escape.yaml"), "out/escape.yaml"]:
            expect("save to " + bad, *request(base + "/api/editor/save", {"path": bad, "doc": doc}), 403, "refused" if not bad.startswith("out") else "leads out of")
        expect("save: body not JSON", *request(base + "/api/editor/save", raw=b"{not json"), 400, "must be a JSON object")
        expect("save: JSON but not an object", *request(base + "/api/editor/save", raw=b"[1,2]"), 400, "must be a JSON object")
        expect("save: no path", *request(base + "/api/editor/save", {"doc": doc}), 400, "missing string field 'path'")
        expect("save: no doc", *request(base + "/api/editor/save", {"path": "x.yaml"}), 400, "missing field 'doc'")
        expect("save: a doc that is no YAML tree", *request(base + "/api/editor/save", {"path": "x.yaml", "doc": {"a": 1}}), 400, "__map")
        expect("save: a bad scenario", *request(base + "/api/editor/save", {"path": "x.yaml", "doc": {"__map": [["dt", "-1"]]}}), 200, '"message":"x.yaml:1: dt: must be in')
        expect("validate a good one", *request(base + "/api/editor/validate", {"path": "copy.yaml", "doc": doc}), 200, '"ok":true')
        expect("run a path out", *request(base + "/api/editor/run", {"path": "../x.yaml"}), 403, "'..' is refused")
        expect("replay a folder out", *request(base + "/api/editor/replay?path=out"), 403, "leads out of")
        expect("live stream in editor mode", *request(base + "/api/stream"), 404, "not a live view")
        expect("unknown API", *request(base + "/api/nothing"), 404, "no such page or API")
        expect("a traversal in the URL", *request(base + "/../../etc/passwd"), 404, "no such page")
        # A request that is not HTTP at all, and one cut short: the server answers or closes, and lives.
        for raw in [b"GARBAGE\r\n\r\n", b"GET /api/info HTTP/1.1\r\nContent-Length: 99999999999999999999\r\n\r\n",
                    b"POST /api/editor/save HTTP/1.1\r\nHost: x\r\nContent-Length: 10\r\n\r\n{\"pa"]:
            host, port = urllib.parse.urlparse(base).hostname, urllib.parse.urlparse(base).port
            with socket.create_connection((host, port), timeout=10) as s:
                s.sendall(raw)
                s.shutdown(socket.SHUT_WR)
                reply = s.recv(200)
            print("raw %-51r -> %r" % (raw[:40], reply[:40]))
        if not os.path.exists(os.path.join(outside, "secret.yaml")) or os.listdir(outside) != ["secret.yaml"]:
            failures.append("something was written outside the editor's folder: %s" % os.listdir(outside))
        if os.path.exists(os.path.join(work, "escape.yaml")):
            failures.append("escape.yaml was written outside the editor's folder")
        expect("still serving", *request(base + "/api/info"), 200, '"mode":"editor"')
        if not view.alive():
            failures.append("hunav_view died")
    finally:
        code = view.stop()
        shutil.rmtree(work, ignore_errors=True)
    if code not in (0, -15):
        failures.append("hunav_view exited with %s after SIGTERM" % code)
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
