"""What the figure scripts of plots/ share: their command line and tables; a figure file appears
whole or not at all.

Each file is written to a hidden temporary file next to it and renamed over it (atomic on one file
system), so an interrupted or failed plot never leaves a half-written PNG or PDF behind. Also used
by the Python package (sglab.plots.save), which ships a copy of this module in sglab._plots.
"""
import csv
import math
import os
import sys

import numpy as np
from matplotlib.ticker import LogLocator, ScalarFormatter


def quick():
    """Whether the command line has --quick (`sglab reproduce --quick`, a first look): figures as PNG
    only (save_figures), no PDF."""
    return "--quick" in sys.argv[1:]


def argv():
    """The command-line arguments but --quick."""
    return [a for a in sys.argv[1:] if a != "--quick"]


def arguments(doc, count):
    """The script's ``count`` command-line arguments (and --quick, anywhere); with any other number,
    prints the usage ``doc`` on stderr and exits with status 2."""
    args = argv()
    if len(args) != count:
        print(doc, file=sys.stderr)
        sys.exit(2)
    return args


def read_table(path):
    """The rows (dicts by column) of a CSV table written by sglab, its provenance lines (those
    starting with '#') skipped."""
    with open(path, newline="") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


# zlib's fastest level for the PNGs of --quick: the same pixels, files about 10 % larger, the
# encoding (a fifth of the stability atlas's CPU at the default level 6) about 40 % cheaper.
QUICK_PNG = {"compress_level": 1}


class _InViewLogLocator(LogLocator):
    """A LogLocator that gives only the locations inside the view interval. An axis makes a tick
    (two lines, a grid line and two texts) for every location its locator gives and then draws only
    those inside the view, and a log locator gives whole decades beyond both ends: on a log-log grid
    of panels those unseen ticks were most of a figure's cost. Keeps every location the axis would
    draw (it allows 1e-10 of the log span beyond each end, this 1e-6), so the pixels are the same.
    With ``labelled_by`` (a formatter; minor ticks in --quick), keeps only the locations it labels."""

    labelled_by = None

    def tick_values(self, vmin, vmax):
        locs = super().tick_values(vmin, vmax)
        lo, hi = sorted((vmin, vmax))
        if not lo > 0 or not math.isfinite(hi):
            return locs
        slack = 1e-6 * (math.log(hi) - math.log(lo))
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.log(np.asarray(locs, dtype=float))
        locs = locs[(t >= math.log(lo) - slack) & (t <= math.log(hi) + slack)]
        if self.labelled_by is not None and len(locs):
            locs = locs[np.array([bool(label) for label in self.labelled_by.format_ticks(locs)])]
        return locs


def lean_log_ticks(fig, labelled_minor_only=False):
    """Makes the log locators of ``fig``'s axes (colour bars' aside) give in-view locations only
    (_InViewLogLocator): the same figure, drawn for a fraction of the cost. With
    ``labelled_minor_only`` (--quick: tight_layout, save_figures), a log axis's minor ticks are kept
    only where they carry a label (no unlabelled minor marks and grid lines in a first look). Call
    it before anything measures or draws the figure (tight_layout); save_figure calls it too."""
    for ax in fig.axes:
        if hasattr(ax, "_colorbar"):
            continue
        for axis in (ax.xaxis, ax.yaxis):
            for ticker in (axis.major, axis.minor):
                # A ScalarFormatter would read the locations it is given; log axes have log formatters.
                if type(ticker.locator) is LogLocator and not isinstance(ticker.formatter, ScalarFormatter):
                    ticker.locator.__class__ = _InViewLogLocator
            if labelled_minor_only and isinstance(axis.minor.locator, _InViewLogLocator):
                axis.minor.locator.labelled_by = axis.minor.formatter


def tight_layout(fig, **kwargs):
    """``fig.tight_layout(**kwargs)`` after lean_log_ticks (labelled minor ticks only with --quick)."""
    lean_log_ticks(fig, quick())
    fig.tight_layout(**kwargs)


def _replace(path, write):
    """Calls ``write(tmp)`` for a hidden temporary file next to ``path`` (the directory created),
    then renames it over ``path``; removes it if ``write`` fails. Returns ``path``."""
    path = os.fspath(path)
    directory, name = os.path.split(path)
    if directory:
        os.makedirs(directory, exist_ok=True)
    tmp = os.path.join(directory, f".{name}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    return path


def save_figure(fig, path, **savefig_args):
    """Writes ``fig`` to ``path`` (format from the extension unless ``format`` is given), through a
    temporary file and a rename (lean_log_ticks first). Creates the directory. Returns ``path``."""
    lean_log_ticks(fig)
    savefig_args.setdefault("format", os.path.splitext(os.fspath(path))[1].lstrip(".") or "png")
    if savefig_args["format"] == "pdf":
        # No creation date in the PDF, so that a rerun writes the same bytes.
        savefig_args.setdefault("metadata", {"CreationDate": None})
    return _replace(path, lambda tmp: fig.savefig(tmp, **savefig_args))


def save_canvas(fig, path, **pil_kwargs):
    """Writes the pixels of ``fig``'s canvas as they stand (drawn, or redrawn in part by blitting)
    to the PNG ``path``, at the figure's dpi (``pil_kwargs``: to PIL's PNG writer), through a
    temporary file and a rename."""
    from matplotlib.image import imsave
    return _replace(path, lambda tmp: imsave(tmp, np.asarray(fig.canvas.buffer_rgba()), format="png", dpi=fig.dpi,
                                             pil_kwargs=pil_kwargs))


def save_figures(fig, out_dir, stem, formats=None, dpi=150, report=False):
    """``fig`` as OUT_DIR/STEM.EXT for each of ``formats`` (save_figure each; default PNG and PDF;
    with --quick PNG only, written with QUICK_PNG, and lean_log_ticks' labelled minor ticks only);
    with ``report``, says so on stderr. Returns the paths."""
    if formats is None:
        formats = ("png",) if quick() else ("png", "pdf")
    lean_log_ticks(fig, quick())
    paths = [save_figure(fig, os.path.join(out_dir, f"{stem}.{ext}"), dpi=dpi,
                         **({"pil_kwargs": QUICK_PNG} if ext == "png" and quick() else {})) for ext in formats]
    if report:
        print("wrote " + " and ".join(paths), file=sys.stderr)
    return paths
