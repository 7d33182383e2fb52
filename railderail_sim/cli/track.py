"""`railderail track-irregularity`: a random sample of a track irregularity spectrum, written as the CSV file
format of docs/track-irregularity.md (mm at this edge), with a one-paragraph summary and, with --plot, the
channels and each component's Welch PSD against the spectrum's formula. Bad options: one line, status 2.
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

from .. import jsonout, plotting


def _band(text):
    """'1,150' -> (1.0, 150.0): the shortest and the longest wavelength in m."""
    parts = text.split(",")
    try:
        band = tuple(float(p) for p in parts)
    except ValueError:
        band = ()
    if len(band) != 2:
        raise argparse.ArgumentTypeError(f"band {text!r} is not two wavelengths in m, e.g. 1,150")
    return band


def _csv_path(text):
    path = Path(text).expanduser()
    if path.suffix.lower() != ".csv":
        raise ValueError(f"output file {text!r} must end in .csv")
    if not (path.parent if str(path.parent) else Path(".")).is_dir():
        raise ValueError(f"output file {text!r}: its folder does not exist")
    return path


def irregularity_command(parser: argparse.ArgumentParser):
    from ..track import irregularity as ir
    from ..track import spectra as sp

    parser.add_argument("--spectrum", required=True, choices=tuple(sp.SPECTRA), metavar="NAME",
                        help=f"one of {', '.join(sp.SPECTRA)}")
    parser.add_argument("--seed", type=int, required=True,
                        help=f"seed of the random phases (an integer in [{ir.SEEDS[0]}, {ir.SEEDS[1]}])")
    parser.add_argument("--length-m", type=float, required=True,
                        help=f"length of the sample ({ir.LENGTH_M[0]:g} m .. {ir.LENGTH_M[1] / 1e3:g} km)")
    parser.add_argument("--out", required=True, metavar="FILE.csv", help="the CSV file to write")
    parser.add_argument("--step-m", type=float, default=0.25,
                        help=f"grid step ({ir.STEP_M[0]:g} .. {ir.STEP_M[1]:g} m, default %(default)s m)")
    parser.add_argument("--band-m", type=_band, default=None, metavar="SHORTEST,LONGEST",
                        help=f"wavelength band inside {ir.BAND_LIMITS_M[0]:g}..{ir.BAND_LIMITS_M[1]:g} m "
                             f"(default: the spectrum's own band)")
    parser.add_argument("--plot", metavar="FILE.png", help="draw the channels and the PSDs against the formula")
    parser.add_argument("--json", action="store_true", help="print the summary as one JSON object")

    def run(args):
        out = _csv_path(args.out)
        plot = plotting.checked_path(args.plot) if args.plot is not None else None
        sample = ir.generate(args.spectrum, args.length_m, args.seed, args.step_m, args.band_m)
        ir.write_csv(sample, out)
        if plot is not None:
            _draw(ir, sample, plot)
        summary = {**sample.summary(), "out": str(out)}
        if plot is not None:
            summary["plot"] = str(plot)
        print(jsonout.dumps(summary) if args.json else _paragraph(summary))
    return run


def _paragraph(summary):
    rms = summary["rms_mm"]
    short, long_ = summary["band_m"]
    return (f"Wrote {summary['out']}: {summary['description']} ({summary['spectrum']}, seed {summary['seed']}), "
            f"{summary['length_m']:g} m at {summary['step_m']:g} m steps, wavelengths {short:.4g} to {long_:.4g} m. "
            f"RMS: left lateral {rms['left_lateral']:.3f} mm, left vertical {rms['left_vertical']:.3f} mm, "
            f"right lateral {rms['right_lateral']:.3f} mm, right vertical {rms['right_vertical']:.3f} mm; "
            f"vertical profile {rms['vertical']:.3f} mm, cross-level {rms['cross_level']:.3f} mm, alignment "
            f"{rms['alignment']:.3f} mm, gauge {rms['gauge']:.3f} mm."
            + (f" Plot: {summary['plot']}." if "plot" in summary else ""))


def _draw(ir, sample, path):
    """Each component's Welch estimate (segments of four longest wavelengths) beside the formula."""
    from ..track import spectra as sp
    spectrum = sp.SPECTRA[sample.spectrum]
    segment_m = 4.0 * sample.band_m[1]
    psds = []
    for component in sp.COMPONENTS:
        omega, estimate = ir.welch_psd(sample, component, segment_m)
        lo, hi = 2.0 * math.pi / sample.band_m[1], 2.0 * math.pi / sample.band_m[0]
        held = (omega >= lo) & (omega <= hi)
        psds.append((ir.COMPONENT_TITLES[component], omega[held], estimate[held],
                     spectrum.psd(component, omega[held])))
    plotting.irregularity_figure(sample, ir.CHANNELS, psds, path)
