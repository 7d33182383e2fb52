"""The project's one plotting module: every figure of railderail is drawn and written here.

One style (STYLE: fonts, sizes, dpi, grid, line widths), a colour per wheel (WHEEL_COLOURS, the left
and right wheel of a wheelset, in every figure that shows wheels) and per critical speed (linear,
nonlinear) wherever it is marked, figures made as
`matplotlib.figure.Figure` without pyplot (no global figure manager, no backend choice), and atomic
writes: the file appears complete or not at all (a temporary file in the same folder, then a rename).
`checked_path` rejects a bad extension or a missing folder with a one-line ValueError; commands call
it before any computation. Inputs are in SI (km/h for speeds, as the methods give them); the figures
label mm, kN, MPa, deg where those read better.

matplotlib is imported only when a figure is drawn, so the commands that import this module for
`checked_path` stay light.
"""
from __future__ import annotations

from contextlib import contextmanager
import math
from pathlib import Path

import numpy as np

from .atomic import atomic_write

FORMATS = (".png", ".pdf", ".svg")
STYLE = {
    "font.size": 9.0,
    "axes.titlesize": 9.0,
    "axes.labelsize": 9.0,
    "xtick.labelsize": 8.0,
    "ytick.labelsize": 8.0,
    "legend.fontsize": 8.0,
    "figure.titlesize": 10.0,
    "lines.linewidth": 1.2,
    "lines.markersize": 4.0,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "grid.linewidth": 0.6,
    "image.cmap": "viridis",
    "figure.dpi": 120,
    "savefig.dpi": 120,
}
WHEEL_COLOURS = {"left": "tab:blue", "right": "tab:red"}
CRITICAL_SPEED_COLOURS = {"linear": "tab:purple", "nonlinear": "tab:brown"}
REFERENCE_COLOUR = "k"                # zero lines, thresholds, Hertz ellipses
MARKER_COLOUR = "0.7"                 # section boundaries and other guides


def checked_path(path) -> Path:
    """The figure file `path` as a Path if its extension is one of FORMATS and its folder exists."""
    p = Path(path).expanduser()
    if p.suffix.lower() not in FORMATS:
        raise ValueError(f"plot file {str(path)!r} must end in {', '.join(FORMATS[:-1])} or {FORMATS[-1]}")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise ValueError(f"plot file {str(path)!r}: its folder {str(parent)!r} does not exist")
    return p


def write_figure(fig, path):
    """Save `fig` to `path` atomically (`atomic.atomic_write`); a file-system error as a ValueError."""
    path = Path(path)
    try:
        with atomic_write(path, "wb") as handle:
            fig.savefig(handle, format=path.suffix.lstrip(".").lower())
    except OSError as error:
        raise ValueError(f"plot file {str(path)!r} cannot be written ({error.strerror or error})") from None


@contextmanager
def figure(path, size):
    """A new Figure of `size` (inches) drawn in STYLE, written atomically to `path` when the block ends."""
    import matplotlib
    from matplotlib.figure import Figure

    path = checked_path(path)
    with matplotlib.rc_context(STYLE):
        fig = Figure(figsize=size, layout="constrained")
        yield fig
        write_figure(fig, path)


# ------------------------------------------------------------------------------------------------
# contact
# ------------------------------------------------------------------------------------------------
WHEEL_DRAWN_ABOVE = 8e-3              # m: the wheel is drawn this far above its contact position


def contact_geometry_figure(result, path):
    """2 x 2 figure of a `methods.contact_geometry.ContactGeometry`: contact points on wheel and rail,
    Delta r(y), contact angles(y) of both wheels, equivalent conicity against amplitude."""
    import matplotlib

    t, pair = result.table, result.pair
    section = result.profile_section()
    y_mm = t.y * 1e3
    lift = WHEEL_DRAWN_ABOVE
    with figure(path, (11.0, 8.0)) as fig:
        ax = fig.subplots(2, 2)
        a = ax[0, 0]
        a.plot(section.rail_y * 1e3, section.rail_z * 1e3, "-", color=REFERENCE_COLOUR, lw=1.5,
               label=f"rail {pair.rail.name}")
        a.plot(section.wheel_y * 1e3, (section.wheel_z + lift) * 1e3, "-", color=WHEEL_COLOURS["left"], lw=1.5,
               label=f"wheel {pair.wheel.name} (+{lift * 1e3:g} mm)")
        cmap = matplotlib.colormaps[STYLE["image.cmap"]]
        y_span = max(abs(t.y[0]), abs(t.y[-1]))
        for shift, (wy, wz), (ry, rz) in zip(section.shift, section.wheel_points, section.rail_points):
            a.plot([wy * 1e3, ry * 1e3], [(wz + lift) * 1e3, rz * 1e3], "-", color=cmap(0.5 + 0.5 * shift / y_span),
                   lw=0.6)
        a.set_xlim(section.wheel_y[0] * 1e3 - 3.0, section.rail_y[-1] * 1e3 + 5.0)
        a.set_ylim(min(-40.0, 1e3 * float((section.wheel_z + lift).min()) - 3.0), 25.0)
        a.set_aspect("equal")
        a.grid(False)
        a.set_xlabel("lateral position from the rail head axis [mm] (left rail, + field side)")
        a.set_ylabel("height [mm]")
        a.set_title(f"contact points, y = {t.y[0] * 1e3:g} ... {t.y[-1] * 1e3:g} mm (colour: y, every 0.5 mm)")
        a.legend(loc="upper right")
        b = ax[0, 1]
        b.plot(y_mm, t.delta_r * 1e3, "-", color=REFERENCE_COLOUR)
        b.set_xlabel("wheelset lateral shift y [mm] (+ left)")
        b.set_ylabel("rolling radius difference r_L - r_R [mm]")
        b.set_title("Delta r(y)")
        c = ax[1, 0]
        c.plot(y_mm, np.degrees(t.contact_angle_left), "-", color=WHEEL_COLOURS["left"], label="left wheel")
        c.plot(y_mm, np.degrees(t.contact_angle_right), "--", color=WHEEL_COLOURS["right"], label="right wheel")
        c.set_xlabel("wheelset lateral shift y [mm] (+ left)")
        c.set_ylabel("contact angle [deg] (+ toward the flange)")
        c.set_title(f"contact angle; max {math.degrees(result.max_contact_angle_rad):.2f} deg, "
                    f"Nadal limit {result.nadal_limit:.3f} at mu {result.friction:g}")
        c.legend()
        d = ax[1, 1]
        rows = result.equivalent_conicity_by_amplitude
        amps = [r.amplitude_m * 1e3 for r in rows]
        d.plot(amps, [r.equivalent_conicity for r in rows], "o-", color=REFERENCE_COLOUR, label="EN 15302 Annex B")
        d.plot(amps, [r.harmonic_conicity for r in rows], "s--", color="0.5", label="harmonic")
        d.axvline(result.equivalent_conicity_amplitude_m * 1e3, color=MARKER_COLOUR, lw=0.8)
        d.set_xlabel("amplitude [mm]")
        d.set_ylabel("equivalent conicity tan(gamma_e) [-]")
        d.set_title(f"equivalent conicity; {result.equivalent_conicity:.4f} at "
                    f"{result.equivalent_conicity_amplitude_m * 1e3:g} mm")
        d.legend()
        fig.suptitle(f"{pair.wheel.name} on {pair.rail.name}, inclination {pair.inclination_text}, gauge "
                     f"{pair.track.gauge * 1e3:g} mm, back-to-back {pair.contact.back_to_back * 1e3:g} mm")


def draw_patch(ax, patch, colour):
    """One `methods.contact_patch.ContactPatch` in its contact plane: the half-space pressure (if solved),
    the discrete (Kik-Piotrowski) outline in the wheel's colour (if computed) and the Hertz ellipse
    (solid when Hertz is the patch's normal model, dashed beside a discrete one)."""
    from matplotlib.patches import Ellipse

    lim = 0.0
    h = patch.halfspace
    if h is not None:
        p = np.where(h.pressure > 0, h.pressure, np.nan) / 1e6
        mesh = ax.pcolormesh(h.s * 1e3, h.x * 1e3, p.T, shading="nearest")
        ax.figure.colorbar(mesh, ax=ax, label="half-space pressure [MPa]", shrink=0.8)
        lim = max(np.max(np.abs(h.x)), np.max(np.abs(h.s))) * 1e3
    q = patch.discrete
    if q is not None:
        inside = q.half_length > 0
        s_mm = np.concatenate(([q.s_edges[0]], q.s[inside], [q.s_edges[1]])) * 1e3
        xl_mm = np.concatenate(([0.0], q.half_length[inside], [0.0])) * 1e3
        ax.plot(np.concatenate((s_mm, s_mm[::-1])), np.concatenate((xl_mm, -xl_mm[::-1])), "-", color=colour,
                label="discrete (Kik-Piotrowski) outline")
        lim = max(lim, np.max(np.abs(s_mm)), np.max(q.half_length) * 1e3)
    a, b = patch.hertz_a_m, patch.hertz_b_m
    ax.add_patch(Ellipse((0.0, 0.0), 2e3 * b, 2e3 * a, fill=False, ls="-" if q is None else "--",
                         color=REFERENCE_COLOUR, lw=1.0, label="Hertz ellipse"))
    lim = 1.15 * max(lim, a * 1e3, b * 1e3)
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")
    ax.set_xlabel("lateral, contact plane [mm] (+ field side)")
    ax.set_ylabel("rolling direction x [mm]")
    ax.legend(loc="upper right")


def patch_figure(path, panels, rows, columns, title=None):
    """A rows x columns grid of patches, filled row by row from `panels`: (patch, wheel side, title), or
    (None, None, text) for a panel without a patch."""
    with figure(path, (max(4.6 * columns, 5.0), 4.0 * rows)) as fig:
        axes = fig.subplots(rows, columns, squeeze=False).ravel()
        for ax in axes[len(panels):]:
            ax.axis("off")
        for ax, (patch, side, text) in zip(axes, panels):
            if patch is None:
                ax.axis("off")
                ax.text(0.5, 0.5, text, ha="center", transform=ax.transAxes)
                continue
            draw_patch(ax, patch, WHEEL_COLOURS[side])
            ax.set_title(text)
        if title:
            fig.suptitle(title)


def contact_case_figure(case, path):
    """The patches of a `methods.contact_case.ContactCase`, one row per wheel, one panel per patch."""
    columns = max(1, max(len(w.patches) for w in case.wheels))
    panels = []
    for w in case.wheels:
        for k in range(columns):
            if k >= len(w.patches):
                panels.append((None, None, f"{w.side} wheel: no patch" if not w.patches else ""))
                continue
            p = w.patches[k]
            panels.append((p, w.side, f"{w.side} wheel, patch {k + 1}: rail y {p.rail_y_m * 1e3:.1f} mm, "
                                      f"{math.degrees(p.contact_angle_rad):.1f} deg\n"
                                      f"N {p.normal_force_N / 1e3:.1f} kN, "
                                      f"{p.length_m * 1e3:.1f} x {p.width_m * 1e3:.1f} mm"))
    pair = case.pair
    patch_figure(path, panels, 2, columns,
                 f"contact-case {pair.wheel.name} / {pair.rail.name}, model {pair.model}\nlateral "
                 f"{case.lateral_m * 1e3:g} mm, yaw {case.yaw_rad * 1e3:g} mrad, load {case.load_N / 1e3:.1f} kN")


# ------------------------------------------------------------------------------------------------
# methods
# ------------------------------------------------------------------------------------------------
def root_locus_figure(result, path):
    """Root locus (real part against frequency, coloured by speed) and least damping ratio against speed
    of a `methods.root_locus.RootLocus`."""
    with figure(path, (12.0, 5.0)) as fig:
        a1, a2 = fig.subplots(1, 2)
        for v, lam in zip(result.speeds_kmh, result.eigenvalues):
            sel = lam.imag / (2 * np.pi) < 20.0
            points = a1.scatter(lam.real[sel], lam.imag[sel] / (2 * np.pi), c=np.full(sel.sum(), v), s=4,
                                vmin=result.speeds_kmh.min(), vmax=result.speeds_kmh.max())
        fig.colorbar(points, ax=a1, label="speed (km/h)")
        a1.axvline(0.0, color=REFERENCE_COLOUR, lw=0.8)
        a1.set_xlabel("real part (1/s)")
        a1.set_ylabel("frequency (Hz)")
        a1.set_xlim(left=max(a1.get_xlim()[0], -40.0))
        a1.set_title("root locus, modes below 20 Hz")
        a2.plot(result.speeds_kmh, 100 * result.least_damping, "-")
        a2.axhline(0.0, color=REFERENCE_COLOUR, lw=0.8)
        if np.isfinite(result.linear_critical_speed_kmh):
            a2.axvline(result.linear_critical_speed_kmh, color=CRITICAL_SPEED_COLOURS["linear"], ls="--",
                       label=f"linear critical speed {result.linear_critical_speed_kmh:.0f} km/h")
            a2.legend()
        a2.set_xlabel("speed (km/h)")
        a2.set_ylabel("least damping ratio (%)")
        a2.set_title("least-damped oscillatory mode")


def limit_cycle_figure(result, path, threshold_m, linear_critical_speed_kmh=None):
    """Final oscillation amplitude against speed of a `methods.limit_cycle.LimitCycle` (Yu 2022, Fig. 2), with
    its bifurcation branches where it has them."""
    with figure(path, (7.0, 4.5)) as fig:
        ax = fig.subplots()
        if len(result.speeds_kmh):
            a = np.where(np.isfinite(result.amplitudes_m), result.amplitudes_m, np.nan) * 1e3
            ax.plot(result.speeds_kmh, a, "o-", label="final amplitude after the excitation")
        for branch, marker in zip(result.branches, ("^-", "v-")):
            a = np.where(np.isfinite(branch.amplitudes_m), branch.amplitudes_m, np.nan) * 1e3
            ax.plot(branch.speeds_kmh, a, marker, ms=4,
                    label=f"{branch.name} branch (kick {branch.kick.amplitude_m * 1e3:g} mm)")
        ax.axhline(threshold_m * 1e3, color=REFERENCE_COLOUR, lw=0.8, ls=":",
                   label=f"{threshold_m * 1e3:g} mm criterion")
        if np.isfinite(result.nonlinear_critical_speed_kmh):
            ax.axvline(result.nonlinear_critical_speed_kmh, color=CRITICAL_SPEED_COLOURS["nonlinear"], ls="--",
                       label=f"nonlinear critical speed ({result.method}) "
                             f"{result.nonlinear_critical_speed_kmh:.0f} km/h")
        if linear_critical_speed_kmh is not None and np.isfinite(linear_critical_speed_kmh):
            ax.axvline(linear_critical_speed_kmh, color=CRITICAL_SPEED_COLOURS["linear"], ls="--",
                       label=f"linear critical speed {linear_critical_speed_kmh:.0f} km/h")
        ax.set_yscale("symlog", linthresh=0.01)
        ax.set_ylim(bottom=0.0)
        ax.set_xlabel("speed (km/h)")
        ax.set_ylabel("wheelset lateral amplitude (mm)")
        ax.legend()
        ax.set_title(f"limit cycle after the excitation: {result.excitation}")


def stability_figure(base, rows, path, required_kmh):
    """The stability study (methods.stability): each one-at-a-time case's nonlinear (ramp-down) and linear
    critical speeds beside the default set's, with the speed the car must be stable to."""
    def kmh(v):
        return np.nan if v is None else float(v)

    with figure(path, (8.0, 0.32 * len(rows) + 1.8)) as fig:
        ax = fig.subplots()
        y = np.arange(len(rows))
        ax.barh(y, [kmh(r["linear_kmh"]) for r in rows], color=CRITICAL_SPEED_COLOURS["linear"], alpha=0.35,
                label="linear (root locus)")
        ax.barh(y, [kmh(r["nonlinear_kmh"]) for r in rows], height=0.5, color=CRITICAL_SPEED_COLOURS["nonlinear"],
                label="nonlinear (ramp-down)")
        ax.axvline(kmh(base["nonlinear_kmh"]), color=CRITICAL_SPEED_COLOURS["nonlinear"], ls="--", lw=0.8,
                   label="default set, nonlinear")
        ax.axvline(required_kmh, color=REFERENCE_COLOUR, ls=":", lw=1.0, label=f"{required_kmh:.0f} km/h")
        ax.set_yticks(y, [f"{r['input']}: {r['value'].split(';')[0].split(',')[0][:40]}" for r in rows], fontsize=7)
        ax.invert_yaxis()
        ax.set_xlabel("critical speed (km/h)")
        ax.legend(fontsize=7, loc="lower right")


def critical_speed_figure(results, path):
    """Critical derailment speed against curve radius (Yu 2022, Fig. 5) from the sweep's result dicts."""
    with figure(path, (7.0, 4.5)) as fig:
        ax = fig.subplots()
        r = [x["radius_m"] for x in results]
        ax.plot(r, [x["critical_derailment_speed_kmh"] for x in results], "o-", label="progressive trial (staircase)")
        if any(x.get("refined_speed_kmh") == x.get("refined_speed_kmh") for x in results):
            ax.plot(r, [x["refined_speed_kmh"] for x in results], "s--",
                    label="bisection, constant speed on Table 2 line")
        ax.set_xlabel("curve radius (m)")
        ax.set_ylabel("critical derailment speed (km/h)")
        ax.legend()


def cwc_figure(curves, path, limit):
    """Characteristic wind curves (EN 14067-6): the gust peak wind speed against the vehicle speed, one curve
    per case ({label: (speeds km/h, wind speeds m/s)})."""
    with figure(path, (7.0, 4.5)) as fig:
        ax = fig.subplots()
        for label, (speeds, winds) in curves.items():
            ax.plot(speeds, winds, "o-", label=label)
        ax.set_xlabel("vehicle speed (km/h)")
        ax.set_ylabel("characteristic wind speed (m/s), gust peak")
        ax.set_title(f"wind at right angles to the track; limit dQ/Q0 = {limit:g} of a running gear")
        ax.legend()


def warning_quality_figure(criteria, runs, path, marked=("attack_angle", 0.06)):
    """Warning quality over a catalogue: per criterion the share of derailments usefully warned (filled) and
    warned at all (open) against the false alarms per 1000 km as its threshold moves (each point labelled
    with its threshold; `marked` = (criterion, threshold) circled), and the leads of each criterion's first
    true alert at its shipped level over the runs (a hazard warned: a derailment or a near miss). The criteria
    on measured signals (rows with signals 'measured') are drawn dashed with square markers."""
    with figure(path, (11.0, 4.8)) as fig:
        roc, leads = fig.subplots(1, 2)
        names = list(dict.fromkeys(row["criterion"] for row in criteria))
        for name in names:
            rows = sorted((r for r in criteria if r["criterion"] == name), key=lambda r: r["threshold"])
            x = [max(r["false_alarms_per_1000_km"], 0.1) for r in rows]      # 0 drawn at the axis' floor
            useful = [r["usefully_warned"] / max(r["derailments"], 1) for r in rows]
            warned = [r["warned"] / max(r["derailments"], 1) for r in rows]
            marker = "s" if rows[0].get("signals") == "measured" else "o"
            line, = roc.plot(x, useful, marker + ("--" if marker == "s" else "-"), label=name.replace("_", " "))
            roc.plot(x, warned, marker + ":", mfc="none", color=line.get_color())
            for r, xi, yi in zip(rows, x, useful):
                roc.annotate(f"{r['threshold']:g}", (xi, yi), fontsize=6, xytext=(2, 2), textcoords="offset points",
                             color=line.get_color())
                if (name, r["threshold"]) == marked:
                    roc.plot(xi, yi, "o", ms=14, mfc="none", mec=REFERENCE_COLOUR)
                    roc.annotate("Yu 2022: 0.06 rad", (xi, yi), xytext=(10, -14), textcoords="offset points",
                                 fontsize=8)
        roc.set_xscale("log")
        roc.set_xlabel("false-alarm episodes per 1000 km of normal running (0 drawn at 0.1)")
        roc.set_ylabel("share of derailments usefully warned (open: warned)")
        roc.legend(fontsize=6, ncol=2)
        data = [[r["first_true_alert"][name]["lead_s"] for r in runs if r["first_true_alert"].get(name)]
                for name in names]
        shown = [(n, d) for n, d in zip(names, data) if d]
        if shown:
            leads.boxplot([d for _, d in shown], orientation="horizontal",
                          tick_labels=[n.replace("_", " ") for n, _ in shown])
            leads.set_xscale("symlog", linthresh=1.0)
        leads.set_xlabel("lead of the first true alert at the shipped level (s)")


def real_track_figure(summaries, path):
    """Critical derailment speed against radius for each (track model, irregularity) of a real-track study
    (`methods.real_track.summary`): the mean over seeds, the bars from the lowest to the highest."""
    with figure(path, (7.5, 4.8)) as fig:
        ax = fig.subplots()
        groups = {}
        for s in summaries:
            groups.setdefault((s["model"], s["irregularity"]), []).append(s)
        for (model, irregularity), ss in groups.items():
            r = np.array([s["radius_m"] for s in ss])
            mean = np.array([s["mean_kmh"] for s in ss], dtype=float)
            low = mean - np.array([s["min_kmh"] for s in ss], dtype=float)
            high = np.array([s["max_kmh"] for s in ss], dtype=float) - mean
            ax.errorbar(r, mean, yerr=np.nan_to_num([low, high]), capsize=3, marker="o" if model == "rigid" else "s",
                        ls="-" if model == "rigid" else "--", label=f"{model}, {irregularity}")
        ax.set_xlabel("curve radius (m)")
        ax.set_ylabel("critical derailment speed (km/h)")
        ax.legend(fontsize="small")


def climb_figure(result, path):
    """One run of the wheel-climb rig (`methods.climb.Climb`): the flanging wheel's L/V and lift against the
    track travelled, the onset of the climb and the flange tip on the rail top marked, Nadal's limit and
    tan(delta) at the largest contact angle as guides."""
    with figure(path, (8.0, 6.0)) as fig:
        ax_lv, ax_lift = fig.subplots(2, 1, sharex=True)
        colour = WHEEL_COLOURS["left"]
        ax_lv.plot(result.distance_m, result.lv, color=colour, lw=0.8, label="left (flanging) wheel")
        ax_lv.axhline(result.nadal_limit, color=REFERENCE_COLOUR, lw=0.8, ls="--",
                      label=f"Nadal's limit {result.nadal_limit:.3f}")
        ax_lv.axhline(math.tan(result.max_contact_angle_rad), color=REFERENCE_COLOUR, lw=0.8, ls=":",
                      label=f"tan(delta), delta = {math.degrees(result.max_contact_angle_rad):.1f} deg")
        ax_lift.plot(result.distance_m, result.lift_m * 1e3, color=colour, lw=0.8, label="wheel lift")
        ax_lift.axhline(result.flange_height_m * 1e3, color=REFERENCE_COLOUR, lw=0.8, ls=":", label="flange height")
        ax_lift.axhline((result.two_point_lift_m + 1e-3) * 1e3, color=MARKER_COLOUR, lw=0.8, ls="--",
                        label="1 mm above two-point contact")
        for ax in (ax_lv, ax_lift):
            if result.climb_position_m is not None:
                ax.axvline(result.climb_position_m, color=MARKER_COLOUR, lw=0.6)
            if result.climb_distance_m is not None:
                ax.axvline(result.climb_position_m + result.climb_distance_m, color=MARKER_COLOUR, lw=0.6)
            ax.legend(fontsize="small")
        ax_lv.set_ylabel("L/V, left wheel")
        ax_lift.set_ylabel("wheel lift (mm)")
        ax_lift.set_xlabel("track travelled (m)")
        lv = f"L/V at the climb {result.climb_lv:.3f}" if result.climb_lv is not None else "no climb"
        distance = (f", climb distance {result.climb_distance_m:.2f} m" if result.climb_distance_m is not None
                    else "")
        fig.suptitle(f"wheel climb, {result.wheel} on {result.rail}: attack angle {result.attack_angle_rad * 1e3:g} "
                     f"mrad, friction {result.friction:g} ({result.creep_law})\n{lv}{distance}")


def climb_sweep_figure(sweep, path):
    """The wheel-climb rig over attack angles (`methods.climb.ClimbSweep`), a curve per friction: the L/V at
    the climb with Nadal's limit at the largest contact angle (dashed), and the climb distance."""
    with figure(path, (10.0, 4.5)) as fig:
        ax_lv, ax_d = fig.subplots(1, 2)
        for mu in sweep.frictions():
            runs = sweep.curve(mu)
            aoa = np.array([c.attack_angle_rad for c in runs]) * 1e3
            lv = np.array([np.nan if c.climb_lv is None else c.climb_lv for c in runs])
            line, = ax_lv.plot(aoa, lv, "o-", label=f"rig, friction {mu:g}")
            ax_lv.plot(aoa, [c.nadal_limit for c in runs], "--", color=line.get_color(), lw=0.8,
                       label=f"Nadal, friction {mu:g}")
            distance = np.array([np.nan if c.climb_distance_m is None else c.climb_distance_m for c in runs])
            ax_d.plot(aoa, distance, "o-", color=line.get_color(), label=f"friction {mu:g}")
        ax_lv.set_xlabel("attack angle (mrad)")
        ax_lv.set_ylabel("L/V at the climb, flanging wheel")
        ax_lv.legend(fontsize="small")
        ax_d.set_xlabel("attack angle (mrad)")
        ax_d.set_ylabel("climb distance (m)")
        ax_d.set_ylim(bottom=0.0)
        ax_d.legend(fontsize="small")
        first = sweep.climbs[0]
        fig.suptitle(f"wheel climb rig, {sweep.wheel} on {sweep.rail}, creep law {first.creep_law}, "
                     f"{first.speed_m_s * 3.6:g} km/h")


def position_figure(path, series, ylabel, markers=(), xlabel="position of the car-body centre (m)"):
    """Quantities against track position: `series` of (position, values, label), guides at `markers`."""
    with figure(path, (8.0, 4.5)) as fig:
        ax = fig.subplots()
        for position, values, label in series:
            ax.plot(position, values, lw=0.8, label=label)
        for s in markers:
            ax.axvline(s, color=MARKER_COLOUR, lw=0.6, ls=":")
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.legend()


def run_figure(result, path):
    """One run against track position (`vehicle.simulate.Result`): the rails' deviations (if irregular),
    the front wheelset's lateral displacement and attack angle, and each of its wheels' Y/Q and lift."""
    irregular = result.scenario.irregularity is not None
    position = result.position
    with figure(path, (8.0, 9.0 if irregular else 7.0)) as fig:
        axes = fig.subplots(4 if irregular else 3, 1, sharex=True)
        if irregular:
            deviation = result.scenario.irregularity.at(position) * 1e3
            for j, name in enumerate(("left lateral", "left vertical", "right lateral", "right vertical")):
                axes[0].plot(position, deviation[:, j], lw=0.6, label=name)
            axes[0].set_ylabel("rail deviation at s (mm)")
            axes[0].legend(ncol=4, fontsize="small")
        ax_y, ax_qp, ax_lift = axes[-3:]
        ax_y.plot(position, result.wheelset_lateral[:, 0] * 1e3, lw=0.8, label="lateral displacement (mm)")
        ax_y.plot(position, result.attack_angle[:, 0] * 1e3, lw=0.8, label="attack angle (mrad)")
        ax_y.set_ylabel("front wheelset")
        ax_y.legend(fontsize="small")
        for k, side in enumerate(("left", "right")):
            ax_qp.plot(position, result.wheel("derailment_coefficient")[:, k], lw=0.6, label=f"{side} wheel")
            ax_lift.plot(position, result.wheel("wheel_lift")[:, k] * 1e3, lw=0.6, label=f"{side} wheel")
        ax_qp.set_ylabel("Y/Q, front wheelset")
        ax_qp.legend(fontsize="small")
        ax_lift.set_ylabel("wheel lift, front wheelset (mm)")
        ax_lift.set_xlabel("position of the car-body centre (m)")
        event = result.derailment
        fig.suptitle(f"R {result.scenario.track.radius:.0f} m, {result.speed[0] * 3.6:.0f} km/h"
                     + (f", {result.scenario.irregularity.name}" if irregular else ", ideal track")
                     + (f": derailed, wheelset {event['wheelset']} {event['wheel_side']}, "
                        f"{event['mechanism'].replace('_', ' ')}" if event else ""))


def assessment_figure(assessment, path):
    """An assessment (`assessment.assess.Assessment`): each quantity's governing value as a share of its
    limit, one bar per quantity and section (a colour per section), the limit at 100 %, failures marked."""
    rows = [r for r in assessment.governing() if r.limit is not None]
    sections = list(dict.fromkeys(r.section for r in rows))
    colours = {name: f"C{k % 10}" for k, name in enumerate(sections)}
    with figure(path, (8.0, 1.2 + 0.22 * max(len(rows), 1))) as fig:
        ax = fig.subplots()
        y = np.arange(len(rows))[::-1]
        share = [100.0 * r.utilisation for r in rows]
        bars = ax.barh(y, share, color=[colours[r.section] for r in rows], height=0.7)
        for bar, r in zip(bars, rows):
            if not r.passes:
                bar.set_hatch("///")
                bar.set_edgecolor(REFERENCE_COLOUR)
        ax.axvline(100.0, color=REFERENCE_COLOUR, lw=1.0)
        ax.set_yticks(y, [f"{r.quantity} ({r.place})" for r in rows], fontsize=7)
        ax.set_xlabel("governing value / limit (%)")
        from matplotlib.patches import Patch
        handles = [Patch(color=colours[name], label=name) for name in sections]
        ax.legend(handles=handles, fontsize="small", loc="lower right")
        ax.set_title(f"{assessment.source}: EN 14363 and comfort, hatched: beyond the limit")


def assessment_study_figure(summaries, quantities, path):
    """The assessment study (`assessment.study`): each case's largest share of each quantity's limit as a
    grid (cases across, quantities down), the share written in each cell, 100 % the limit."""
    grid = np.full((len(quantities), len(summaries)), np.nan)
    for j, s in enumerate(summaries):
        for i, q in enumerate(quantities):
            shares = [r["utilisation"] for r in s["governing"] if r["quantity"] == q and r["utilisation"] is not None]
            if shares:
                grid[i, j] = 100.0 * max(shares)
    with figure(path, (1.6 + 0.55 * len(summaries), 1.8 + 0.35 * len(quantities))) as fig:
        ax = fig.subplots()
        image = ax.imshow(grid, cmap="RdYlGn_r", vmin=0.0, vmax=150.0, aspect="auto")
        for (i, j), value in np.ndenumerate(grid):
            if np.isfinite(value):
                ax.text(j, i, f"{value:.0f}", ha="center", va="center", fontsize=6,
                        fontweight="bold" if value > 100.0 else "normal")
        ax.set_xticks(range(len(summaries)), [f"R {s['case']['radius']:.0f}\n{s['case']['irregularity']}\n"
                                              f"{s['case']['model']}\n{s['speed_kmh']:.0f} km/h" for s in summaries],
                      fontsize=6)
        ax.set_yticks(range(len(quantities)), quantities)
        ax.grid(False)
        fig.colorbar(image, ax=ax, label="largest value / limit (%)", shrink=0.8)
        ax.set_title("EN 14363 quantities and Sperling's index at the permitted speed (100 % = the limit)")


# ------------------------------------------------------------------------------------------------
# track
# ------------------------------------------------------------------------------------------------
MAX_DRAWN_POINTS = 100_000            # a longer channel is drawn at every k-th point (the figure cannot show more)


def irregularity_figure(sample, channels, psds, path):
    """A track irregularity (`track.irregularity.Irregularity`): its lateral and vertical rail channels
    against s (`channels` names the columns of sample.values) and, per component, the sample's Welch PSD
    beside the spectrum's formula, log-log; `psds` rows (title, omega rad/m, estimate, formula)."""
    stride = max(1, math.ceil(len(sample.s) / MAX_DRAWN_POINTS))
    s = sample.s[::stride]
    with figure(path, (11.0, 10.0)) as fig:
        ax = fig.subplots(3, 2)
        for a, direction in zip(ax[0], ("lateral", "vertical")):
            for side in ("left", "right"):
                column = channels.index(f"{side}_{direction}")
                a.plot(s, sample.values[::stride, column] * 1e3, lw=0.6, color=WHEEL_COLOURS[side],
                       label=f"{side} rail")
            a.set_xlabel("s (m)" + (f", every {stride}th point" if stride > 1 else ""))
            a.set_ylabel(f"{direction} deviation (mm, + {'left' if direction == 'lateral' else 'up'})")
            a.legend(loc="upper right")
        for a, (title, omega, estimate, formula) in zip(ax[1:].ravel(), psds):
            a.loglog(omega, estimate, lw=0.8, color="0.5", label="sample (Welch)")
            a.loglog(omega, formula, lw=1.2, color=REFERENCE_COLOUR, label="spectrum")
            a.set_xlabel("spatial angular frequency (rad/m)")
            a.set_ylabel("PSD (m^2/(rad/m))")
            a.set_title(title)
            a.legend(loc="lower left")
        short, long_ = sample.band_m
        fig.suptitle(f"{sample.description}; seed {sample.seed}, wavelengths {short:.4g} to {long_:.4g} m")



def survey_figure(result, permitted, targets, path):
    """A survey's speed profile along the line (`methods.survey.SurveyResult`): the permitted speed
    (`permitted`: (start m, end m, m/s) pieces), each curve's critical derailment speed (dotted where no
    derailment came up to it) and safe speed over its extent, each defect's safe speed, and the most
    restrictive profile (`targets`: (start m, end m, m/s, reason) pieces), against km."""
    def stairs(ax, pieces, **style):
        ax.stairs([p[2] * 3.6 for p in pieces], np.array([pieces[0][0]] + [p[1] for p in pieces]) / 1000.0,
                  baseline=None, **style)

    with figure(path, (9.0, 4.5)) as fig:
        ax = fig.subplots()
        stairs(ax, permitted, color="tab:green", lw=3.5, alpha=0.6, label="permitted speed")
        for i, c in enumerate(result.curves):
            km = np.array([c["start_m"], c["end_m"]]) / 1000.0
            ax.plot(km, [c["critical_derailment_speed_kmh"]] * 2, color="tab:red", lw=2.0,
                    ls="-" if c["derailed"] else ":", label="critical derailment speed" if i == 0 else None)
            ax.plot(km, [c["safe_speed_kmh"]] * 2, color="tab:orange", lw=2.0, label="safe speed" if i == 0 else None)
        for i, d in enumerate(result.defects):
            ax.plot(d["position_m"] / 1000.0, d["safe_speed_kmh"], "v", color="tab:purple",
                    label="defect: safe speed" if i == 0 else None)
        stairs(ax, targets, color=REFERENCE_COLOUR, lw=0.8, label="most restrictive profile")
        ax.set_xlabel("position along the line (km)")
        ax.set_ylabel("speed (km/h)")
        ax.set_title(f"{result.line['name']}: dotted where no derailment came up to the staircase's top")
        ax.legend(loc="lower left")
