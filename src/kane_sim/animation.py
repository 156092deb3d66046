"""The mechanism moving, for notebooks and files: kane_sim.animate(result) draws the two rods,
the sliders on their rail and the spring frame by frame from a run's q1, q2 (positions from the
C++ model's geometry, kane_sim._core.mechanism_points), as a matplotlib animation.

In a notebook: `kane_sim.animate(r, html=True)` shows it inline (JavaScript player, no ffmpeg
needed); `kane_sim.animate(r, save="run.gif")` writes a GIF (Pillow)."""
from collections.abc import Mapping

import numpy as np

from kane_sim import _core
from kane_sim import plotting  # noqa: F401  (picks a headless backend when there is no display)

import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import animation as mpl_animation  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

# Frame (0) has x (i) pointing down; the screen draws y to the right and x downwards.


def _screen(points):
    """(x, y) in frame (0) -> (right, up) on screen."""
    return points[..., 1], -points[..., 0]


def _spring(b, c, turns=8, width=0.03):
    """A zigzag from B to C (screen coordinates) along the rail."""
    (bx, by), (cx, cy) = b, c
    s = np.linspace(0, 1, 2 * turns + 3)
    offsets = np.zeros_like(s)
    offsets[1:-1:2] = width
    offsets[2:-1:2] = -width
    offsets[1] = offsets[-2] = 0
    return bx + (cx - bx) * s + offsets, by + (cy - by) * s


def animate(result, rod_half_length=None, fps=25, speed=1.0, save=None, html=False,
            title="Kane equations - Example 1"):
    """An animation of a run. result: a kane_sim.Result (or columns t, q1, q2, torque);
    rod_half_length: L [m] (default: the run's config); fps: frames per second of the video;
    speed: sim seconds per video second. save: a .gif (or any writer matplotlib has) to write;
    html: return the notebook's inline player (IPython HTML) instead of the animation."""
    if not isinstance(result, Mapping):
        raise TypeError("animate: result must be a kane_sim.Result (or a mapping of columns t, "
                        "q1, q2), got %s" % type(result).__name__)
    if rod_half_length is None:
        config = getattr(result, "config", None)
        if config is None:
            raise ValueError("animate: give rod_half_length (L [m]) for data without a config")
        rod_half_length = config["mechanism.rod_half_length"]
    if not (fps > 0 and speed > 0):
        raise ValueError("animate: fps and speed must be > 0, got %r and %r" % (fps, speed))
    t = np.asarray(result["t"], dtype=float)
    if len(t) < 2:
        raise ValueError("animate: the run has %d rows, at least 2 are needed" % len(t))
    # Frames at fps video frames per second: the row at or just before each frame's sim time.
    frame_times = np.arange(t[0], t[-1] + 1e-12, speed / fps)
    rows = np.clip(np.searchsorted(t, frame_times, side="right") - 1, 0, len(t) - 1)
    q1 = np.asarray(result["q1"], dtype=float)[rows]
    q2 = np.asarray(result["q2"], dtype=float)[rows]
    torque = (np.asarray(result["applied_torque"], dtype=float)[rows]
              if "applied_torque" in result else None)
    points = _core.mechanism_points(float(rod_half_length), q1, q2)
    O, A, B, C = (np.column_stack(_screen(points[k])) for k in ("O", "A", "B", "C"))

    L = rod_half_length
    block_w, block_h = 0.6 * L, 0.28 * L
    everything = np.vstack([O, A, B, C])
    margin = 0.6 * L
    fig, ax = plt.subplots(figsize=(5, 6), dpi=80)
    ax.set_xlim(everything[:, 0].min() - margin, everything[:, 0].max() + margin)
    ax.set_ylim(everything[:, 1].min() - margin, everything[:, 1].max() + margin)
    ax.set_aspect("equal")
    ax.set_title(title, fontsize="medium")
    ax.set_xlabel("y [m]")
    ax.set_ylabel("-x [m] (x points down)")
    ax.axvline(0.0, color="lightgray", linewidth=4, zorder=0)  # the rail, through O along x
    ax.plot([0], [0], marker="^", color="black", markersize=10, zorder=5)  # pivot O
    rod1, = ax.plot([], [], color="tab:blue", linewidth=4, solid_capstyle="round", label="rod 1")
    rod2, = ax.plot([], [], color="tab:orange", linewidth=4, solid_capstyle="round",
                    label="rod 2")
    spring, = ax.plot([], [], color="tab:green", linewidth=1.5, label="spring k")
    pins, = ax.plot([], [], "o", color="black", markersize=5, zorder=6)
    slider3 = Rectangle((0, 0), block_w, block_h, color="tab:red", alpha=0.8, label="slider 3")
    slider4 = Rectangle((0, 0), block_w, block_h, color="tab:purple", alpha=0.8,
                        label="slider 4")
    ax.add_patch(slider3)
    ax.add_patch(slider4)
    text = ax.text(0.02, 0.98, "", transform=ax.transAxes, va="top", family="monospace",
                   fontsize="small")
    ax.legend(loc="lower right", fontsize="x-small")
    fig.tight_layout()

    def draw(i):
        rod1.set_data([O[i, 0], A[i, 0]], [O[i, 1], A[i, 1]])
        rod2.set_data([A[i, 0], B[i, 0]], [A[i, 1], B[i, 1]])
        spring.set_data(*_spring(B[i], C[i], width=0.25 * L))
        pins.set_data([A[i, 0], B[i, 0]], [A[i, 1], B[i, 1]])
        slider3.set_xy((B[i, 0] - block_w / 2, B[i, 1] - block_h / 2))
        slider4.set_xy((C[i, 0] - block_w / 2, C[i, 1] - block_h / 2))
        label = "t = %6.2f s\nq1 = %6.1f deg" % (frame_times[i], np.degrees(q1[i]))
        if torque is not None:
            label += "\nM_m = %6.2f N m" % torque[i]
        text.set_text(label)
        return rod1, rod2, spring, pins, slider3, slider4, text

    anim = mpl_animation.FuncAnimation(fig, draw, frames=len(rows), interval=1000.0 / fps,
                                       blit=True)
    if save:
        writer = mpl_animation.PillowWriter(fps=fps) if str(save).endswith(".gif") else None
        anim.save(str(save), writer=writer)
    if html:
        from IPython.display import HTML
        player = HTML(anim.to_jshtml())
        plt.close(fig)
        return player
    return anim
