#!/usr/bin/python3
"""Checks an rviz screenshot: the mechanism's marker colours are drawn inside the 3D view.

The 3D view is found as the bounding box of rviz's background colour (config/kane_sim.rviz:
40;40;48); rods (blue), sliders (orange) and spring (green), from src/markers.cpp, must each
cover enough pixels inside it. With --setpoint, also the crank_marker's ring and arrow (yellow,
MarkerColors::kSetpoint; the ring half transparent on the background). Exit 0 when all are
there, 1 otherwise, with the counts.
With --attached, also the torque arrow (red, in rod 1's frame at A; the largest red blob, not the
TF axes): drawn, and touching a rod (its nearest rod pixel within 12 px), as it is when markers and links are placed with the same
transform; in a fast replay the arrow drawn from the message's positions hung 0.4 m off.
Exit 3 with --attached when the mechanism is drawn but the arrow cannot be judged (too short, or
cut by the view's edge).
Usage: check_screenshot.py SHOT.png [--setpoint] [--attached]
"""
import sys

import matplotlib.image
import numpy as np

# Minimum pixel counts, at 1280x800: the rods cover ~3000 px, the sliders ~1000 px, the spring
# ~300 px in the reference shot; a quarter of that rules out stray pixels but tolerates
# the mechanism being drawn in another pose.
COLOURS = {
    "rods (blue)": (lambda r, g, b: (b > 0.6) & (r < 0.35) & (g < 0.5) & (b > g + 0.25), 700),
    "sliders (orange)": (lambda r, g, b: (r > 0.8) & (g > 0.35) & (g < 0.75) & (b < 0.25), 250),
    "spring (green)": (lambda r, g, b: (g > 0.6) & (r < 0.4) & (b < 0.4), 60),
}
# The ring covers ~11000 px in the reference shot (scale 0.6 m); r close to g tells it from the
# sliders' orange (g ~ 0.55 r).
SETPOINT = ("crank setpoint ring (yellow)",
            (lambda r, g, b: (r > 0.45) & (g > 0.38) & (b < 0.3) & (np.abs(r - g) < 0.2), 2500))


TORQUE = lambda r, g, b: (r > 0.6) & (g < 0.25) & (b < 0.25)
ROD = COLOURS["rods (blue)"][0]


def largest_component(pixels):
    """The largest 8-connected set among (row, col) pixels: the arrow, not the TF display's thin
    red x axes."""
    left = set(map(tuple, pixels))
    best = []
    while left:
        seed = left.pop()
        component, frontier = [seed], [seed]
        while frontier:
            y, x = frontier.pop()
            for dy in (-1, 0, 1):
                for dx in (-1, 0, 1):
                    n = (y + dy, x + dx)
                    if n in left:
                        left.remove(n)
                        component.append(n)
                        frontier.append(n)
        if len(component) > len(best):
            best = component
    return np.array(best)


def arrow_touches_a_rod(r, g, b, inside, view):
    arrow = largest_component(np.argwhere(TORQUE(r, g, b) & inside))
    top, bottom, left, right = view
    if len(arrow) and (arrow[:, 0].min() <= top + 2 or arrow[:, 0].max() >= bottom - 2
                       or arrow[:, 1].min() <= left + 2 or arrow[:, 1].max() >= right - 2):
        print("ok   torque arrow (red): cut by the view's edge, not judged")
        return None
    rods = np.argwhere(ROD(r, g, b) & inside)
    if len(rods) == 0:
        print("FAIL torque arrow: no rod drawn")
        return False
    if len(arrow) < 100:  # a torque near zero draws a stub (or nothing): nothing to judge
        print("ok   torque arrow (red): %d px, too short to judge" % len(arrow))
        return None
    step_a, step_r = max(1, len(arrow) // 600), max(1, len(rods) // 1500)
    a, rod = arrow[::step_a].astype(float), rods[::step_r].astype(float)
    gap = np.sqrt(((a[:, None, :] - rod[None, :, :]) ** 2).sum(axis=2)).min()
    ok = gap <= 12
    print("%s torque arrow (red): %d px, %.1f px from the nearest rod pixel (need <= 12)"
          % ("ok  " if ok else "FAIL", len(arrow), gap))
    return ok


def main(path, setpoint=False, attached=False):
    image = matplotlib.image.imread(path)
    if image.ndim == 2:  # ImageMagick writes a grey screen (rviz not up yet) as a grey PNG
        image = np.stack([image] * 3, axis=2)
    image = image[:, :, :3].astype(float)
    if image.max() > 1.0:
        image /= 255.0
    r, g, b = image[:, :, 0], image[:, :, 1], image[:, :, 2]
    background = (np.abs(r - 40 / 255) < 0.02) & (np.abs(g - 40 / 255) < 0.02) & (np.abs(b - 48 / 255) < 0.02)
    # The view's rows and columns are mostly background; panels and toolbars are not.
    cols = np.nonzero(background.mean(axis=0) > 0.3)[0]
    rows = np.nonzero(background.mean(axis=1) > 0.3)[0]
    if len(rows) < 100 or len(cols) < 100:
        print("FAIL: no 3D view with rviz's background colour in %s" % path)
        return 1
    top, bottom, left, right = rows.min(), rows.max(), cols.min(), cols.max()
    print("3D view: x %d..%d, y %d..%d of %dx%d" % (left, right, top, bottom, image.shape[1], image.shape[0]))
    inside = np.zeros(background.shape, dtype=bool)
    inside[top:bottom + 1, left:right + 1] = True
    failures = 0
    checks = dict(COLOURS)
    if setpoint:
        checks[SETPOINT[0]] = SETPOINT[1]
    for name, (match, minimum) in checks.items():
        mask = match(r, g, b)
        count_in, count_out = int((mask & inside).sum()), int((mask & ~inside).sum())
        ok = count_in >= minimum
        failures += not ok
        print("%s %s: %d px inside the 3D view (need %d), %d outside"
              % ("ok  " if ok else "FAIL", name, count_in, minimum, count_out))
    if attached:
        verdict = arrow_touches_a_rod(r, g, b, inside, (top, bottom, left, right))
        if verdict is False:
            failures += 1
        elif verdict is None and not failures:
            return 3  # drawn, but the arrow cannot be judged in this shot
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], setpoint="--setpoint" in sys.argv[2:],
                  attached="--attached" in sys.argv[2:]))
