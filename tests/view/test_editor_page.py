"""The editor through the page's controls: open a scenario, drag a person with the mouse, change its
behavior in the form, add a wall, save; the saved file has the edits, and loads (hunav_run runs it).
Then the people of an agents file (HuNavSim's own agents.yaml) edited with a scenario that names it,
a generator's region dragged and its count changed (crowd.yaml), and the run button: the edited
scenario runs in the server and its replay shows. Last, a page of another origin that POSTs to the
editor (no-cors text/plain, a guessed token, a text/plain form) writes nothing (issue 31)."""
import json
import os
import shutil
import subprocess
import sys
import tempfile

from cdp import GENEROUS, Browser
from viewproc import View


def canvas_origin(browser):
    return browser.eval("(() => { const r = document.getElementById('canvas').getBoundingClientRect();"
                        " return [r.left, r.top]; })()")


def open_file(browser, path):
    browser.eval("document.getElementById('ed-files').value = %r; document.getElementById('ed-open').click()" % path)
    browser.wait_for("window.hunavView.app.ed && window.hunavView.app.ed.path === %r" % path)
    browser.eval("window.hunavView.redraw()")


def set_field(browser, name, value):
    browser.wait_for("document.querySelector('#ed-props [name=%s]')" % name)
    browser.eval("{ const f = document.querySelector('#ed-props [name=%s]'); f.value = %r;"
                 " f.dispatchEvent(new Event('change')); }" % (name, value))


def save_as(browser, path, saves):
    browser.eval("document.getElementById('ed-path').value = %r; document.getElementById('ed-save').click()" % path)
    try:
        browser.wait_for("window.hunavView.app.ed.saved === %d" % saves)
    except AssertionError:
        print("status:", browser.eval("document.getElementById('ed-status').textContent"), browser.js_errors())
        raise


def agents_file_and_generator_and_run(browser, root, repo, problems):
    import yaml
    # HuNavSim's agents.yaml (tests/data/hunav_files, MIT) named by a scenario: an open room around it.
    os.makedirs(os.path.join(root, "room"))
    shutil.copy(os.path.join(repo, "tests", "data", "hunav_files", "agents.yaml"),
                os.path.join(root, "room", "agents.yaml"))
    with open(os.path.join(root, "room", "room.yaml"), "w") as f:
        f.write("name: room\ndt: 0.01\ntime_limit: 10.0\nseed: 1\nmap:\n  walls:\n"
                "    - [[-15, -15], [15, -15], [15, 15], [-15, 15], [-15, -15]]\n"
                "robot:\n  radius: 0.3\n  start: {x: 12.0, y: 0.0, yaw: 3.14159}\n"
                "  goal: {x: -12.0, y: 0.0, radius: 0.3}\n"
                "people: agents.yaml\n")
    browser.eval("window.hunavView.editor.files()", await_promise=True)
    open_file(browser, "room/room.yaml")
    status = browser.eval("document.getElementById('ed-status').textContent")
    if "room/agents.yaml" not in status:
        problems.append("opening room.yaml does not say its people are in room/agents.yaml: %r" % status)
    agent = browser.eval("window.hunavView.drawn.editor.find((h) => h.role === 'person' && h.name === 'agent4')")
    if agent is None:
        problems.append("the people of the agents file are not drawn as handles")
        return
    scale = browser.eval("window.hunavView.view.scale")
    left, top = canvas_origin(browser)
    x0, y0 = agent["px"] + left, agent["py"] + top
    browser.drag(x0, y0, x0 + 20, y0)
    want_x = round(agent["x"] + 20 / scale, 2)
    set_field(browser, "type", "curious")
    save_as(browser, "room/room.yaml", 1)
    agents = yaml.safe_load(open(os.path.join(root, "room", "agents.yaml")))["hunav_loader"]["ros__parameters"]
    a4 = agents["agent4"]
    if abs(a4["init_pose"]["x"] - want_x) > 0.011 or a4["behavior"]["type"] != "curious":
        problems.append("agents.yaml's agent4 saved as %s / %r, want x %s, curious"
                        % (a4["init_pose"], a4["behavior"], want_x))
    if yaml.safe_load(open(os.path.join(root, "room", "room.yaml")))["people"] != "agents.yaml":
        problems.append("the scenario no longer names its agents file")
    if agents["agents"] != ["agent1", "agent2", "agent7", "agent4", "agent5"]:
        problems.append("the agents list changed: %s" % agents["agents"])

    # The generator of crowd.yaml: drag its region's centre (a diamond), set its count in the form.
    open_file(browser, "scenarios/crowd.yaml")
    region = browser.eval("window.hunavView.drawn.editor.find((h) => h.role === 'region')")
    if region is None:
        problems.append("crowd.yaml's generator region is not drawn")
        return
    scale = browser.eval("window.hunavView.view.scale")
    left, top = canvas_origin(browser)
    browser.drag(region["px"] + left, region["py"] + top, region["px"] + left + 30, region["py"] + top)
    dx = round(30 / scale, 2)
    set_field(browser, "count", "40")
    save_as(browser, "scenarios/crowd_edited.yaml", 1)
    gen = yaml.safe_load(open(os.path.join(root, "scenarios", "crowd_edited.yaml")))["people"]["generate"]
    if gen["count"] != 40:
        problems.append("the generator's count saved as %r" % gen["count"])
    if abs(gen["region"]["x"][0] - (4.0 + dx)) > 0.011 or abs(gen["region"]["x"][1] - (46.0 + dx)) > 0.011 \
            or gen["region"]["y"] != [1.0, 29.0]:
        problems.append("the region saved as %s, dragged by %s m in x from x [4, 46]" % (gen["region"], dx))
    # The scene is checked again by the server after the save: wait for its answer (a busy machine
    # can take longer than the save's own round trip), then look.
    try:
        browser.wait_for("window.hunavView.app.ed.scene && window.hunavView.app.ed.scene.agents.length === 40")
    except AssertionError:
        pass
    drawn_people = browser.eval("window.hunavView.app.ed.scene.agents.length")
    if drawn_people != 40:
        problems.append("the checked scene holds %s generated people, not 40" % drawn_people)

    # run: saves, runs in the server (sfw), and replays the result.
    open_file(browser, "scenarios/passing.yaml")
    browser.eval("document.getElementById('ed-planner').value = 'sfw'; document.getElementById('ed-run').click()")
    browser.wait_for("window.hunavView.app.lastRun && window.hunavView.app.replay")
    run = browser.eval("window.hunavView.app.lastRun")
    status = browser.eval("document.getElementById('ed-status').textContent")
    print("run:", run, status)
    run_json = os.path.join(root, run["out_dir"], "run.json")
    if run["status"] != "goal_reached" or not os.path.exists(run_json):
        problems.append("the run button's run: %s (run.json there: %s)" % (run, os.path.exists(run_json)))
    elif json.load(open(run_json))["fingerprint"] != run["fingerprint"] or "sfw" not in run["out_dir"]:
        problems.append("the run shown is not the run written: %s" % run)
    frames = browser.eval("window.hunavView.app.replay.frameCount")
    if not frames or browser.eval("window.hunavView.app.editing"):
        problems.append("after run the page does not replay it (%s frames)" % frames)


def cross_origin_pages_cannot_write(browser, view, root, problems):
    """Issue 31: a page of another origin that the user visits POSTs to the editor (a no-cors
    text/plain fetch, a fetch with a guessed token, a text/plain form): nothing is written."""
    import http.server
    import threading
    import urllib.request
    with urllib.request.urlopen(view.url + "/api/editor/open?path=scenarios/passing.yaml", timeout=GENEROUS) as r:
        doc = json.load(r)["doc"]
    target = view.url + "/api/editor/save"

    def body(name):
        return json.dumps({"path": name, "doc": doc})
    page = """<!doctype html><html><body>
<form id="f" method="post" action="%s" enctype="text/plain" target="sink"><input name='%s' value='"}'></form>
<iframe name="sink" id="sink"></iframe>
<script>
const target = %s;
Promise.allSettled([
  fetch(target, {method: 'POST', mode: 'no-cors', headers: {'Content-Type': 'text/plain'}, body: %s}),
  fetch(target, {method: 'POST', headers: {'Content-Type': 'application/json', 'X-HuNav-Token': '0'.repeat(32)},
                 body: %s}),
]).then((r) => {
  window.results = r.map((x) => x.status);
  document.getElementById('sink').onload = () => { document.title = 'done'; };
  document.getElementById('f').submit();
});
</script></body></html>""" % (
        target, body("evil_form.yaml")[:-1].replace("'", "&#39;") + ', "pad": "',
        json.dumps(target), json.dumps(body("evil_fetch.yaml")), json.dumps(body("evil_cors.yaml")))

    class Handler(http.server.BaseHTTPRequestHandler):
        def do_GET(self):
            self.send_response(200)
            self.send_header("Content-Type", "text/html")
            self.end_headers()
            self.wfile.write(page.encode())

        def log_message(self, *args):
            pass
    server = http.server.HTTPServer(("127.0.0.1", 0), Handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        browser.call("Page.navigate", url="http://127.0.0.1:%d/" % server.server_address[1])
        browser.wait_for("document.title === 'done'")
        print("cross-origin fetches:", browser.eval("window.results"))
    finally:
        server.shutdown()
    written = [f for f in os.listdir(root) if f.startswith("evil_")]
    if written:
        problems.append("a page of another origin wrote %s" % written)


def main():
    repo, bindir = os.environ["REPO"], os.environ["BIN"]
    work = tempfile.mkdtemp(prefix="hunav_view_editor.")
    root = os.path.join(work, "root")
    shutil.copytree(os.path.join(repo, "scenarios"), os.path.join(root, "scenarios"))
    view = View(["--no-live", "--editor", root])
    browser = Browser()
    problems = []
    try:
        browser.goto(view.url + "/")
        files = browser.eval("window.hunavView.editor.files()", await_promise=True)
        if "scenarios/cafe.yaml" not in files:
            problems.append("the file list misses scenarios/cafe.yaml: %s" % files)
        # Open cafe.yaml with the controls: choose it in the list, press open.
        browser.eval("document.getElementById('ed-files').value = 'scenarios/cafe.yaml';"
                     " document.getElementById('ed-open').click()")
        browser.wait_for("window.hunavView.app.ed && window.hunavView.app.ed.path === 'scenarios/cafe.yaml'")
        browser.eval("window.hunavView.redraw()")
        agent = browser.eval("window.hunavView.drawn.editor.find((h) => h.role === 'person' && h.name === 'agent3')")
        scale = browser.eval("window.hunavView.view.scale")
        # Drag agent3 by (+10, -40) px: (+10/scale, +40/scale) m, north, clear of walls and tables. Mouse events
        # are in the window's pixels, the drawn positions in the canvas's.
        left, top = canvas_origin(browser)
        x0, y0 = agent["px"] + left, agent["py"] + top
        browser.drag(x0, y0, x0 + 10, y0 - 40)
        want_x = round(agent["x"] + 10 / scale, 2)
        want_y = round(agent["y"] + 40 / scale, 2)
        # The form of the selected person: its behavior becomes 'scared'.
        browser.wait_for("document.querySelector('#ed-props select[name=type]')")
        browser.eval("{ const s = document.querySelector('#ed-props select[name=type]'); s.value = 'scared';"
                     " s.dispatchEvent(new Event('change')); }")
        # A wall through the button, then save under a new name with the save button.
        browser.eval("document.getElementById('ed-add-wall').click()")
        browser.eval("document.getElementById('ed-path').value = 'scenarios/cafe_edited.yaml';"
                     " document.getElementById('ed-save').click()")
        try:
            browser.wait_for("window.hunavView.app.ed.saved === 1")
        except AssertionError:
            print("status:", browser.eval("document.getElementById('ed-status').textContent"), browser.js_errors())
            raise
        status = browser.eval("document.getElementById('ed-status').textContent")
        print("status:", status)
        saved = os.path.join(root, "scenarios", "cafe_edited.yaml")
        text = open(saved).read()
        import yaml  # Debian's python3-yaml
        doc = yaml.safe_load(text)
        a3 = doc["people"]["hunav_loader"]["ros__parameters"]["agent3"]
        if abs(a3["init_pose"]["x"] - want_x) > 0.011 or abs(a3["init_pose"]["y"] - want_y) > 0.011:
            problems.append("agent3 saved at (%s, %s), dragged to (%s, %s)"
                            % (a3["init_pose"]["x"], a3["init_pose"]["y"], want_x, want_y))
        if a3["behavior"]["type"] != "scared":
            problems.append("agent3's behavior saved as %r" % a3["behavior"]["type"])
        if len(doc["map"].get("walls", [])) != 1:
            problems.append("the added wall is not in the file: %s" % doc["map"])
        # Untouched keys stay: the other agents and the map file.
        agent_names = doc["people"]["hunav_loader"]["ros__parameters"]["agents"]
        if doc["map"]["map_server"] != "maps/map_cafe2.yaml" or len(agent_names) != 6:
            problems.append("untouched keys changed")
        # A bad value through a field shows the loader's file:line: key next to the field.
        # Select agent3 again with a click where it was dragged to.
        browser.mouse("mousePressed", x0 + 10, y0 - 40)
        browser.mouse("mouseReleased", x0 + 10, y0 - 40, buttons=0)
        browser.wait_for("document.querySelector('#ed-props input[name=max_vel]')")
        browser.eval("{ const f = document.querySelector('#ed-props input[name=max_vel]'); f.value = '-3';"
                     " f.dispatchEvent(new Event('change')); }")
        browser.wait_for("document.querySelector('#ed-props .field.bad')")
        err = browser.eval("document.querySelector('#ed-props .field.bad .field-error').textContent")
        print("field error:", err)
        if "scenarios/cafe_edited.yaml:" not in err or "max_vel" not in err:
            problems.append("the error next to the field is %r" % err)
        # hunav_run runs the saved file.
        r = subprocess.run([os.path.join(bindir, "hunav_run"), "--scenario", saved, "--duration", "2", "--out",
                            os.path.join(work, "out")], capture_output=True, text=True)
        if r.returncode != 0:
            problems.append("hunav_run on the saved file: %s %s" % (r.returncode, r.stderr[-500:]))
        agents_file_and_generator_and_run(browser, root, repo, problems)
        errors = browser.js_errors()
        if errors:
            problems.append("JavaScript errors: %s" % errors)
        cross_origin_pages_cannot_write(browser, view, root, problems)
    finally:
        browser.close()
        view.stop()
        shutil.rmtree(work, ignore_errors=True)
    for p in problems:
        print("FAIL:", p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
