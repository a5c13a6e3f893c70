"""Top view of a simulation as an RGB numpy array, drawn with numpy alone (no matplotlib).

Walls are dark grey lines, the robot a blue disc with a white heading tick, its goal a green ring,
people discs coloured by behavior (regular grey, impassive brown, surprised yellow, scared purple,
curious cyan, threatening red) and drawn darker while their reaction is active.
"""
import numpy as np

BACKGROUND = (255, 255, 255)
WALL = (60, 60, 60)
ROBOT = (30, 90, 220)
GOAL = (20, 170, 60)
# Indexed by HuNavSim behavior code 1..6 (0: unknown).
BEHAVIOR_COLORS = {
    0: (128, 128, 128), 1: (150, 150, 150), 2: (150, 100, 50), 3: (230, 200, 0),
    4: (140, 60, 200), 5: (0, 190, 200), 6: (220, 30, 30),
}


class Canvas:
    """An RGB image mapping world metres to pixels (x right, y up)."""

    def __init__(self, bounds, width=None, height=None, resolution=0.05):
        x0, y0, x1, y1 = (float(b) for b in bounds)
        if width is None:
            width = max(1, int(np.ceil((x1 - x0) / resolution)))
        if height is None:
            height = max(1, int(np.ceil((y1 - y0) / resolution)))
        self.scale = min(width / (x1 - x0), height / (y1 - y0))
        self.x0, self.y0 = x0, y0
        self.width, self.height = int(width), int(height)
        self.image = np.empty((self.height, self.width, 3), dtype=np.uint8)
        self.image[:] = BACKGROUND

    def to_pixels(self, x, y):
        col = (np.asarray(x, dtype=float) - self.x0) * self.scale
        row = self.height - 1 - (np.asarray(y, dtype=float) - self.y0) * self.scale
        return col, row

    def line(self, x0, y0, x1, y1, color, thickness=1):
        """A segment in world coordinates, sampled at half-pixel steps."""
        c0, r0 = self.to_pixels(x0, y0)
        c1, r1 = self.to_pixels(x1, y1)
        n = int(max(abs(c1 - c0), abs(r1 - r0)) * 2) + 2
        t = np.linspace(0.0, 1.0, n)
        cols = c0 + (c1 - c0) * t
        rows = r0 + (r1 - r0) * t
        half = thickness // 2
        for dc in range(-half, thickness - half):
            for dr in range(-half, thickness - half):
                self._plot(rows + dr, cols + dc, color)

    def disc(self, x, y, radius, color, ring=False):
        """A filled disc (or a ring two pixels wide) of `radius` metres."""
        cc, rc = self.to_pixels(x, y)
        rp = max(radius * self.scale, 1.0)
        r0, r1 = int(max(0, np.floor(rc - rp - 1))), int(min(self.height, np.ceil(rc + rp + 2)))
        c0, c1 = int(max(0, np.floor(cc - rp - 1))), int(min(self.width, np.ceil(cc + rp + 2)))
        if r0 >= r1 or c0 >= c1:
            return
        rows, cols = np.mgrid[r0:r1, c0:c1]
        d = np.hypot(rows - rc, cols - cc)
        mask = (d <= rp) & (d >= rp - 2.0) if ring else d <= rp
        self.image[r0:r1, c0:c1][mask] = color

    def _plot(self, rows, cols, color):
        rows = np.round(rows).astype(int)
        cols = np.round(cols).astype(int)
        keep = (rows >= 0) & (rows < self.height) & (cols >= 0) & (cols < self.width)
        self.image[rows[keep], cols[keep]] = color


def render_top_view(sim, width=None, height=None, resolution=0.05):
    """The top view of `sim` (a hunav.Simulation after reset()) as a (height, width, 3) uint8 array.

    Without width/height the image has one pixel per `resolution` metres of the scenario's bounds.
    """
    world = sim.map()
    canvas = Canvas(world["bounds"], width, height, resolution)
    for x0, y0, x1, y1 in world["segments"]:
        canvas.line(x0, y0, x1, y1, WALL, thickness=2)
    for x, y, r in world["circles"]:
        canvas.disc(x, y, r, WALL)
    robot = sim.robot
    if robot["has_goal"]:
        gx, gy, _, gr = robot["goal"]
        canvas.disc(gx, gy, max(gr, 0.1), GOAL, ring=True)
    state = sim.state()
    agents = state["agents"]
    for (x, y, _), r, beh, active in zip(agents["pose"], agents["radius"], agents["behavior"],
                                         agents["behavior_state"]):
        color = np.array(BEHAVIOR_COLORS.get(int(beh), BEHAVIOR_COLORS[0]))
        canvas.disc(x, y, r, tuple((color * (0.6 if active else 1.0)).astype(np.uint8)))
    x, y, yaw = state["robot"][:3]
    radius = state["robot"][6]
    canvas.disc(x, y, radius, ROBOT)
    canvas.line(x, y, x + radius * np.cos(yaw), y + radius * np.sin(yaw), (255, 255, 255), thickness=2)
    return canvas.image
