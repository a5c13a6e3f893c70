"""hunav_view refuses paths out of the editor's folder (.., absolute, symlinks), malformed requests
(bodies that are not JSON, nest too deep or are too large; text that is not UTF-8) and requests that
are not its page's (another Host or Origin, a POST without the page's token) with clear errors, and
keeps serving. Saves of different files at once each keep their own document, a save to the folder
itself or a run with a planner named "../x" writes nothing outside the folder. Each case below failed
before its fix (issue 31): the process died (invalid UTF-8, deep JSON), a file was written (a cross-origin
text/plain POST, Host: evil.example), or a file or folder appeared outside the editor's folder."""
import json
import os
import shutil
import socket
import sys
import tempfile
import threading
import urllib.parse

from cdp import GENEROUS
from viewproc import View


def hostile_cases(view, root, work, doc, expect, failures):
    """The hostile requests of issue 31, one by one; each left the server dead or wrote a file."""
    port = urllib.parse.urlparse(view.url).port
    save = "/api/editor/save"
    good = {"path": "origin.yaml", "doc": doc}
    # Not the page's: no token, a wrong one, another site's Origin, another Host, a text/plain body.
    expect("save without the page's token", *view.request(save, good, token=False), 403, "X-HuNav-Token")
    expect("save with a wrong token", *view.request(save, good, token="0" * 32), 403, "X-HuNav-Token")
    expect("save from another origin", *view.request(save, good, headers={"Origin": "http://evil.example"}), 403,
           "cross-origin")
    expect("save from origin null", *view.request(save, good, headers={"Origin": "null"}), 403, "cross-origin")
    expect("save for Host evil.example", *view.request(save, good, headers={"Host": "evil.example"}), 403,
           "host 'evil.example'")
    expect("read for Host evil.example", *view.request("/api/editor/files", headers={"Host": "evil.example"}), 403,
           "host 'evil.example'")
    expect("the page for Host evil.example", *view.request("/", headers={"Host": "evil.example:%d" % port}), 403,
           "refused")
    expect("a cross-origin text/plain save (no preflight)",
           *view.request(save, good, token=False,
                         headers={"Origin": "http://evil.example", "Content-Type": "text/plain"}),
           403, "cross-origin")
    expect("a text/plain save with the token", *view.request(save, good, headers={"Content-Type": "text/plain"}), 415,
           "application/json")
    if os.path.exists(os.path.join(root, "origin.yaml")):
        failures.append("a refused request wrote origin.yaml")
    expect("save from the page's own origin", *view.request(save, good, headers={"Origin": view.url}), 200, '"ok":true')
    expect("save from localhost", *view.request(save, good, headers={"Host": "localhost:%d" % port,
                                                                     "Origin": "http://localhost:%d" % port}), 200,
           '"ok":true')
    # Text that is not UTF-8: in a query parameter, in a path, in a file of the folder.
    expect("open with invalid UTF-8 in the path parameter", *view.request("/api/editor/open?path=%FF%FE.yaml"), 400,
           "not UTF-8")
    expect("replay with invalid UTF-8 in the path parameter", *view.request("/api/editor/replay?path=a%C0%AF"), 400,
           "not UTF-8")
    expect("a URL path that is not UTF-8", *view.request("/api/%FF"), 400, "not UTF-8")
    with open(os.path.join(root, "latin1.yaml"), "wb") as f:
        f.write(b"name: caf\xe9\xff\ndt: 0.01\n")
    expect("open a file that is not UTF-8", *view.request("/api/editor/open?path=latin1.yaml"), 200, "caf\ufffd")
    with open(os.path.join(os.fsencode(root), b"caf\xe9.yaml"), "w") as f:
        f.write("name: x\n")
    expect("list a file whose name is not UTF-8", *view.request("/api/editor/files"), 200, "caf\ufffd.yaml")
    # JSON that nests deep (parsing it overflowed the stack: SIGSEGV), or is too large, or is no UTF-8.
    deep = b"[" * 300000 + b"]" * 300000
    expect("a body of 300000 nested arrays", *view.request(save, raw=deep), 400, "nests deeper")
    nested = b'{"path": "d.yaml", "doc": ' + b'{"a":' * 1000 + b'1' + b'}' * 1001
    expect("a doc nested 1000 deep", *view.request(save, raw=nested), 400, "nests deeper")
    # A body larger than 8 MB: refused from its Content-Length (the server does not read it).
    with socket.create_connection(("127.0.0.1", port), timeout=GENEROUS) as sock:
        sock.sendall(("POST %s HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nContent-Type: application/json\r\n"
                      "X-HuNav-Token: %s\r\nContent-Length: %d\r\n\r\n" % (save, port, view.token(), 9 << 20)).encode())
        reply = b""
        while b"}" not in reply:
            chunk = sock.recv(4096)
            if not chunk:
                break
            reply += chunk
    head, _, text = reply.decode(errors="replace").partition("\r\n\r\n")
    expect("a body larger than 8 MB", int(head.split(" ")[1]) if head.startswith("HTTP/") else 0, text, 413,
           "larger than")
    expect("a body that is not UTF-8", *view.request(save, raw=b'{"path": "\xff.yaml", "doc": {}}'), 400, "UTF-8")
    # Writes aimed at the folder itself or beside it, and runs whose planner names a folder out of it.
    for target in [".", "./", "", "sub/..", "view_runs"]:
        status, text = view.request(save, {"path": target, "doc": doc})
        expect("save to %r" % target, status, text, 403, "")
    for planner in ["../../escape", "dwb/../../../escape", "nonesuch"]:
        expect("run with planner %r" % planner,
               *view.request("/api/editor/run", {"path": "passing.yaml", "planner": planner}), 400, "unknown planner")
    expect("run with a duration that is no number",
           *view.request("/api/editor/run", {"path": "passing.yaml", "duration": "x"}), 400, "duration")
    # Saves of different files at once, through the server's threads: each file keeps its own document.
    errors = []

    def writer(k):
        mine = json.loads(json.dumps(doc))
        for kv in mine["__map"]:
            if kv[0] == "name":
                kv[1] = "writer%d" % k
        for _ in range(8):
            status, text = view.request(save, {"path": "w%d.yaml" % k, "doc": mine})
            if status != 200 or '"ok":true' not in text:
                errors.append("writer %d: %d %s" % (k, status, text[:200]))
    threads = [threading.Thread(target=writer, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    failures.extend(errors)
    for k in range(8):
        with open(os.path.join(root, "w%d.yaml" % k)) as f:
            if "name: writer%d\n" % k not in f.read():
                failures.append("w%d.yaml does not hold writer %d's document" % (k, k))
    print("8 concurrent writers x 8 saves: %d errors" % len(errors))


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

    def request(url, body=None, raw=None, method=None, headers=None, token=True):
        return view.request(url[len(base):], body=body, raw=raw, method=method, headers=headers, token=token)
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
        def q(p):
            return base + "/api/editor/open?path=" + urllib.parse.quote(p)
        save = base + "/api/editor/save"
        expect("open a file inside", *request(q("passing.yaml")), 200, '"path":"passing.yaml"')
        expect("open ../", *request(q("../outside/secret.yaml")), 403, "'..' is refused")
        expect("open an absolute path", *request(q(os.path.join(outside, "secret.yaml"))), 403,
               "absolute paths are refused")
        expect("open a symlinked file out", *request(q("evil.yaml")), 403, "leads out of")
        expect("open through a symlinked folder", *request(q("out/secret.yaml")), 403, "leads out of")
        expect("open a missing file", *request(q("nothing.yaml")), 403, "no such file")
        expect("open without a path", *request(base + "/api/editor/open"), 400, "missing query parameter 'path'")
        doc = json.loads(request(q("passing.yaml"))[1])["doc"]
        for bad in ["../escape.yaml", os.path.join(work, "escape.yaml"), "out/escape.yaml"]:
            expect("save to " + bad, *request(save, {"path": bad, "doc": doc}), 403,
                   "refused" if not bad.startswith("out") else "leads out of")
        expect("save: body not JSON", *request(save, raw=b"{not json"), 400, "must be a JSON object")
        expect("save: JSON but not an object", *request(save, raw=b"[1,2]"), 400, "must be a JSON object")
        expect("save: no path", *request(save, {"doc": doc}), 400, "missing string field 'path'")
        expect("save: no doc", *request(save, {"path": "x.yaml"}), 400, "missing field 'doc'")
        expect("save: a doc that is no YAML tree", *request(save, {"path": "x.yaml", "doc": {"a": 1}}), 400, "__map")
        expect("save: a bad scenario", *request(save, {"path": "x.yaml", "doc": {"__map": [["dt", "-1"]]}}), 200,
               '"message":"x.yaml:1: dt: must be in')
        expect("validate a good one", *request(base + "/api/editor/validate", {"path": "copy.yaml", "doc": doc}), 200,
               '"ok":true')
        expect("run a path out", *request(base + "/api/editor/run", {"path": "../x.yaml"}), 403, "'..' is refused")
        expect("replay a folder out", *request(base + "/api/editor/replay?path=out"), 403, "leads out of")
        expect("live stream in editor mode", *request(base + "/api/stream"), 404, "not a live view")
        expect("unknown API", *request(base + "/api/nothing"), 404, "no such page or API")
        expect("a traversal in the URL", *request(base + "/../../etc/passwd"), 404, "no such page")
        # A request that is not HTTP at all, and one cut short: the server answers or closes, and lives.
        for raw in [b"GARBAGE\r\n\r\n", b"GET /api/info HTTP/1.1\r\nContent-Length: 99999999999999999999\r\n\r\n",
                    b"POST /api/editor/save HTTP/1.1\r\nHost: x\r\nContent-Length: 10\r\n\r\n{\"pa"]:
            host, port = urllib.parse.urlparse(base).hostname, urllib.parse.urlparse(base).port
            with socket.create_connection((host, port), timeout=GENEROUS) as s:
                s.sendall(raw)
                s.shutdown(socket.SHUT_WR)
                reply = s.recv(200)
            print("raw %-51r -> %r" % (raw[:40], reply[:40]))
        hostile_cases(view, root, work, doc, expect, failures)
        if not os.path.exists(os.path.join(outside, "secret.yaml")) or os.listdir(outside) != ["secret.yaml"]:
            failures.append("something was written outside the editor's folder: %s" % os.listdir(outside))
        if os.path.exists(os.path.join(work, "escape.yaml")):
            failures.append("escape.yaml was written outside the editor's folder")
        expect("still serving", *request(base + "/api/info"), 200, '"mode":"editor"')
        if not view.alive():
            failures.append("hunav_view died")
        if sorted(os.listdir(work)) != ["outside", "root"]:
            failures.append("files appeared beside the editor's folder: %s" % sorted(os.listdir(work)))
        left = [os.path.join(d, f) for d, _, fs in os.walk(work) for f in fs if f.startswith(".hunav_view_")]
        if left:
            failures.append("temporary files left: %s" % left)
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
