"""Checks what the page drew against the positions the world published."""
from cdp import hex_rgb

# Read in one evaluation: redraw the latest frame, then the drawn positions, the view transform and
# the canvas colour at each drawn centre.
SNAPSHOT_JS = """(() => {
  const v = window.hunavView; const d = v.redraw();
  const px = (p) => v.pixel(p.px, p.py);
  return { t: d.t, tick: d.tick, scale: v.view.scale, ox: v.view.ox, oy: v.view.oy,
           robot: Object.assign({ rgba: px(d.robot) }, d.robot),
           people: d.people.map((p) => Object.assign({ rgba: px(p) }, p)) };
})()"""

COLORS = {0: "#444444", 1: "#1f77b4", 2: "#7f7f7f", 3: "#e6b800", 4: "#9467bd", 5: "#2ca02c", 6: "#d62728"}


def compare(snapshot, expected, tolerance_px=1.5):
    """expected: states_at(...) of the snapshot's time. Returns a list of problems (empty: fine) and
    how many centres were checked by colour."""
    problems = []
    s = snapshot["scale"]

    def to_px(x, y):
        return (snapshot["ox"] + x * s, snapshot["oy"] - y * s)
    if "robot" not in expected:
        return ["no states.csv rows at t=%r" % snapshot["t"]], 0
    ids = sorted(k for k in expected if k != "robot")
    drawn_ids = sorted(p["id"] for p in snapshot["people"])
    if ids != drawn_ids:
        problems.append("t=%r: people drawn %s, published %s" % (snapshot["t"], drawn_ids, ids))
    entities = [("robot", snapshot["robot"], expected["robot"][:2], 0)]
    for p in snapshot["people"]:
        if p["id"] in expected:
            entities.append((p["id"], p, expected[p["id"]][:2], expected[p["id"]][2]))
    colour_checked = 0
    for name, drawn, (x, y), behavior in entities:
        ex, ey = to_px(x, y)
        err = ((drawn["px"] - ex) ** 2 + (drawn["py"] - ey) ** 2) ** 0.5
        if err > tolerance_px:
            problems.append("t=%r: %s drawn at (%.1f, %.1f) px, published (%.3f, %.3f) m = (%.1f, %.1f) px" %
                            (snapshot["t"], name, drawn["px"], drawn["py"], x, y, ex, ey))
        # The colour at the centre, where no other body overlaps it (3 radii).
        crowded = any(other is not drawn
                      and ((other["px"] - drawn["px"]) ** 2 + (other["py"] - drawn["py"]) ** 2) ** 0.5
                      < 3 * max(drawn.get("r", 5), 5) for _, other, _, _ in entities)
        if crowded:
            continue
        want = hex_rgb(COLORS[behavior])
        got = drawn["rgba"][:3]
        if max(abs(a - b) for a, b in zip(want, got)) > 40:
            problems.append("t=%r: %s's centre has colour %s, its behavior's is %s" % (snapshot["t"], name, got, want))
        colour_checked += 1
    return problems, colour_checked
