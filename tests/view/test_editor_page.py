"""The editor through the page's controls: open a scenario, drag a person with the mouse, change its
behavior in the form, add a wall, save; the saved file has the edits, and loads (hunav_run runs it)."""
import os
import shutil
import subprocess
import sys
import tempfile

from cdp import Browser
from viewproc import View


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
        browser.eval("document.getElementById('ed-files').value = 'scenarios/cafe.yaml'; document.getElementById('ed-open').click()")
        browser.wait_for("window.hunavView.app.ed && window.hunavView.app.ed.path === 'scenarios/cafe.yaml'", 10)
        browser.eval("window.hunavView.redraw()")
        agent = browser.eval("window.hunavView.drawn.editor.find((h) => h.role === 'person' && h.name === 'agent3')")
        scale = browser.eval("window.hunavView.view.scale")
        # Drag agent3 by (+10, -40) px: (+10/scale, +40/scale) m, north, clear of walls and tables. Mouse events are in the window's
        # pixels, the drawn positions in the canvas's.
        left, top = browser.eval("(() => { const r = document.getElementById('canvas').getBoundingClientRect(); return [r.left, r.top]; })()")
        x0, y0 = agent["px"] + left, agent["py"] + top
        browser.drag(x0, y0, x0 + 10, y0 - 40)
        want_x = round(agent["x"] + 10 / scale, 2)
        want_y = round(agent["y"] + 40 / scale, 2)
        # The form of the selected person: its behavior becomes 'scared'.
        browser.wait_for("document.querySelector('#ed-props select[name=type]')", 5)
        browser.eval("{ const s = document.querySelector('#ed-props select[name=type]'); s.value = 'scared'; s.dispatchEvent(new Event('change')); }")
        # A wall through the button, then save under a new name with the save button.
        browser.eval("document.getElementById('ed-add-wall').click()")
        browser.eval("document.getElementById('ed-path').value = 'scenarios/cafe_edited.yaml'; document.getElementById('ed-save').click()")
        try:
            browser.wait_for("window.hunavView.app.ed.saved === 1", 15)
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
            problems.append("agent3 saved at (%s, %s), dragged to (%s, %s)" % (a3["init_pose"]["x"], a3["init_pose"]["y"], want_x, want_y))
        if a3["behavior"]["type"] != "scared":
            problems.append("agent3's behavior saved as %r" % a3["behavior"]["type"])
        if len(doc["map"].get("walls", [])) != 1:
            problems.append("the added wall is not in the file: %s" % doc["map"])
        # Untouched keys stay: the other agents and the map file.
        if doc["map"]["map_server"] != "maps/map_cafe2.yaml" or len(doc["people"]["hunav_loader"]["ros__parameters"]["agents"]) != 6:
            problems.append("untouched keys changed")
        # A bad value through a field shows the loader's file:line: key next to the field.
        # Select agent3 again with a click where it was dragged to.
        browser.mouse("mousePressed", x0 + 10, y0 - 40)
        browser.mouse("mouseReleased", x0 + 10, y0 - 40, buttons=0)
        browser.wait_for("document.querySelector('#ed-props input[name=max_vel]')", 5)
        browser.eval("{ const f = document.querySelector('#ed-props input[name=max_vel]'); f.value = '-3'; f.dispatchEvent(new Event('change')); }")
        browser.wait_for("document.querySelector('#ed-props .field.bad')", 10)
        err = browser.eval("document.querySelector('#ed-props .field.bad .field-error').textContent")
        print("field error:", err)
        if "scenarios/cafe_edited.yaml:" not in err or "max_vel" not in err:
            problems.append("the error next to the field is %r" % err)
        # hunav_run runs the saved file.
        r = subprocess.run([os.path.join(bindir, "hunav_run"), "--scenario", saved, "--duration", "2", "--out",
                            os.path.join(work, "out")], capture_output=True, text=True)
        if r.returncode != 0:
            problems.append("hunav_run on the saved file: %s %s" % (r.returncode, r.stderr[-500:]))
        errors = browser.js_errors()
        if errors:
            problems.append("JavaScript errors: %s" % errors)
    finally:
        browser.close()
        view.stop()
        shutil.rmtree(work, ignore_errors=True)
    for p in problems:
        print("FAIL:", p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
