"""Small static SVG charts for the HTML report: bars with error whiskers, heatmaps, x-y lines and points.

Each chart is a self-contained ``<svg>`` string (a ``viewBox``, so it scales to the page width) that a
browser draws without JavaScript; every mark carries a ``<title>`` with its values, shown on hover.
Series are ``<g class="series" data-series="k">`` groups and their legend entries
``<g class="legend-item" data-series="k">``, which the report's script toggles on click. Text is
escaped; numbers are written with four significant digits so a chart of a few hundred marks stays a few
tens of kilobytes.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from html import escape

import numpy as np

COLORS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
          "#bcbd22", "#17becf")
"""matplotlib's tab10, so the SVG charts match the PNGs."""
WIDTH = 640.0
"""View-box width of every chart [px]; the page scales it to the column width."""
FONT = 11.0


def _f(v: float) -> str:
    """A coordinate with one decimal."""
    return f"{v:.1f}".rstrip("0").rstrip(".")


def num(v: float) -> str:
    """A value for a tooltip or tick: four significant digits, ``nan`` for a missing value."""
    return "nan" if v is None or not np.isfinite(v) else f"{v:.4g}"


def _text(x: float, y: float, s: str, anchor: str = "start", size: float = FONT, extra: str = "") -> str:
    return (f'<text x="{_f(x)}" y="{_f(y)}" font-size="{size:g}" text-anchor="{anchor}"{extra}>'
            f"{escape(s)}</text>")


@dataclass
class Scale:
    """A linear or logarithmic map from data values to pixels."""

    lo: float
    hi: float
    a: float
    b: float
    log: bool = False

    def __post_init__(self) -> None:
        if self.log:
            self.lo, self.hi = math.log10(self.lo), math.log10(self.hi)
        if not self.hi > self.lo:
            pad = abs(self.lo) * 0.05 or 1.0
            self.lo, self.hi = self.lo - pad, self.hi + pad

    def __call__(self, v: float) -> float:
        v = math.log10(v) if self.log else v
        return self.a + (v - self.lo) / (self.hi - self.lo) * (self.b - self.a)

    def ticks(self, n: int = 5) -> list[float]:
        """Round tick values inside the range (decades on a log scale)."""
        if self.log:
            first, last = math.ceil(self.lo - 1e-9), math.floor(self.hi + 1e-9)
            step = max(1, math.ceil((last - first + 1) / (n + 2)))     # at most ~n + 2 decades labelled
            return [10.0 ** k for k in range(first, last + 1, step)]
        step = 10 ** math.floor(math.log10((self.hi - self.lo) / n))
        step *= next(m for m in (1, 2, 2.5, 5, 10) if (self.hi - self.lo) / (step * m) <= n)
        first = math.ceil(self.lo / step - 1e-9)
        return [k * step for k in range(first, int(math.floor(self.hi / step + 1e-9)) + 1)]


def _range(values: Sequence[float], log: bool = False, include: Sequence[float] = ()) -> tuple[float, float]:
    """The finite (and, on a log scale, positive) extent of ``values`` and ``include``, padded by 4 %."""
    v = np.asarray([*values, *include], float)
    v = v[np.isfinite(v) & ((v > 0) if log else True)]
    if not v.size:
        return (1.0, 10.0) if log else (0.0, 1.0)
    lo, hi = float(v.min()), float(v.max())
    if log:
        return lo / 1.15, hi * 1.15
    pad = 0.04 * (hi - lo) or 0.05 * (abs(hi) or 1.0)
    return lo - pad, hi + pad


def _svg(height: float, body: list[str], label: str) -> str:
    return (f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {_f(WIDTH)} {_f(height)}" role="img" '
            f'aria-label="{escape(label)}" font-family="sans-serif">' + "".join(body) + "</svg>")


def _legend(labels: Sequence[str], x: float, y: float, colors: Sequence[str] | None = None) -> list[str]:
    """Legend entries in a row from (x, y), wrapping at the chart width; ``colors``: each swatch's
    colour (default: :data:`COLORS` in order)."""
    out, cx, cy = [], x, y
    for k, lab in enumerate(labels):
        w = 22 + 6.2 * len(lab)
        if cx + w > WIDTH - 10 and cx > x:
            cx, cy = x, cy + 16
        style = f'fill="{colors[k] if colors else COLORS[k % len(COLORS)]}"'
        out.append(f'<g class="legend-item" data-series="{k}"><rect x="{_f(cx)}" y="{_f(cy - 9)}" width="12" '
                   f'height="10" {style}/>' + _text(cx + 16, cy, lab) + "</g>")
        cx += w
    return out


def legend_height(labels: Sequence[str], x: float = 60.0) -> float:
    """Height the legend rows of :func:`_legend` take [px]."""
    rows, cx = 1, x
    for lab in labels:
        w = 22 + 6.2 * len(lab)
        if cx + w > WIDTH - 10 and cx > x:
            rows, cx = rows + 1, x
        cx += w
    return 16.0 * rows


@dataclass
class Bars:
    """One series of a horizontal bar chart: a value per category with optional error half-widths;
    ``faded`` marks (untrusted) bars drawn pale with a dashed outline."""

    label: str
    values: Sequence[float]
    errors: Sequence[float] | None = None
    faded: Sequence[bool] | None = None


def bar_chart(categories: Sequence[str], series: Sequence[Bars], xlabel: str, title: str = "",
              xlim: tuple[float, float] | None = None) -> str:
    """Horizontal grouped bars, one group per category, one bar per series, whiskers for the errors."""
    left = 10 + 6.0 * max((len(c) for c in categories), default=4)
    left = min(max(left, 60.0), 0.4 * WIDTH)
    top = 22.0 + (16 if title else 0) + legend_height([s.label for s in series], left)
    bar_h = max(4.0, min(12.0, 40.0 / max(len(series), 1)))
    group = bar_h * len(series) + 6
    height = top + group * len(categories) + 40
    vals = [v for s in series for v in s.values]
    errs = [v + (e if np.isfinite(e) else 0) * sgn for s in series for v, e in
            zip(s.values, s.errors if s.errors is not None else [0.0] * len(s.values)) for sgn in (-1, 1)]
    lo, hi = xlim or _range([*vals, *errs], include=[0.0])
    x = Scale(lo, hi, left, WIDTH - 14)
    body = [_text(WIDTH / 2, 14, title, "middle", 12, ' font-weight="bold"')] if title else []
    body += _legend([s.label for s in series], left, top - 10 - legend_height([s.label for s in series], left) + 16)
    body += _x_axis(x, top - 4, top + group * len(categories), xlabel)
    for i, c in enumerate(categories):
        y0 = top + i * group
        body.append(_text(left - 5, y0 + group / 2 + 3, c, "end", 10))
    zero = x(max(min(0.0, x.hi), x.lo))
    for k, s in enumerate(series):
        color = COLORS[k % len(COLORS)]
        marks = [f'<g class="series" data-series="{k}" fill="{color}" stroke="{color}">']
        for i, v in enumerate(s.values):
            if not np.isfinite(v):
                continue
            y0 = top + i * group + 3 + k * bar_h
            x0, x1 = sorted((zero, x(min(max(v, x.lo), x.hi))))
            faded = bool(s.faded[i]) if s.faded is not None else False
            err = s.errors[i] if s.errors is not None else float("nan")
            tip = f"{categories[i]}, {s.label}: {num(v)}" + (f" ± {num(err)}" if np.isfinite(err) else "") \
                + (" (untrusted)" if faded else "")
            style = ' fill-opacity="0.3" stroke-dasharray="3 2"' if faded else ' stroke-width="0"'
            marks.append(f'<rect x="{_f(x0)}" y="{_f(y0)}" width="{_f(max(x1 - x0, 0.8))}" height="{_f(bar_h - 1)}"'
                         f'{style}><title>{escape(tip)}</title></rect>')
            if np.isfinite(err) and err > 0:
                ym = y0 + (bar_h - 1) / 2
                a, b = x(max(v - err, x.lo)), x(min(v + err, x.hi))
                marks.append(f'<path d="M{_f(a)} {_f(ym)}H{_f(b)}" stroke="#333" stroke-width="1"/>')
        body += marks + ["</g>"]
    return _svg(height, body, title or xlabel)


def _x_axis(x: Scale, y_top: float, y_bottom: float, label: str) -> list[str]:
    out = [f'<path d="M{_f(x.a)} {_f(y_bottom)}H{_f(x.b)}" stroke="#333"/>']
    for t in x.ticks():
        px = x(t)
        out.append(f'<path d="M{_f(px)} {_f(y_top)}V{_f(y_bottom + 4)}" stroke="#ddd"/>')
        out.append(_text(px, y_bottom + 15, num(t), "middle", 10))
    out.append(_text((x.a + x.b) / 2, y_bottom + 32, label, "middle"))
    return out


def _y_axis(y: Scale, x_left: float, x_right: float, label: str) -> list[str]:
    out = [f'<path d="M{_f(x_left)} {_f(y.a)}V{_f(y.b)}" stroke="#333"/>']
    for t in y.ticks():
        py = y(t)
        out.append(f'<path d="M{_f(x_left - 4)} {_f(py)}H{_f(x_right)}" stroke="#ddd"/>')
        out.append(_text(x_left - 6, py + 3, num(t), "end", 10))
    mid = (y.a + y.b) / 2
    out.append(_text(14, mid, label, "middle", extra=f' transform="rotate(-90 14 {_f(mid)})"'))
    return out


@dataclass
class Line:
    """One series of an x-y chart: a line with markers, or markers only (``points``); optional band
    ``(low, high)`` drawn shaded; ``hollow`` marks drawn as open circles (untrusted)."""

    label: str
    x: Sequence[float]
    y: Sequence[float]
    band: tuple[Sequence[float], Sequence[float]] | None = None
    points: bool = False
    hollow: Sequence[bool] | None = None
    notes: Sequence[str] | None = None
    color: int | None = None
    """Index into :data:`COLORS` (default: the series' position), so a name keeps its colour across charts."""


@dataclass
class Guide:
    """A reference line through two points in data coordinates (e.g. ``y = x``), grey and unlabelled
    in the legend; ``label`` is its tooltip."""

    x: tuple[float, float]
    y: tuple[float, float]
    label: str = ""


def xy_chart(series: Sequence[Line], xlabel: str, ylabel: str, title: str = "", xlog: bool = False,
             ylog: bool = False, guides: Sequence[Guide] = (), xlim: tuple[float, float] | None = None,
             ylim: tuple[float, float] | None = None, height: float = 300.0) -> str:
    """Lines and markers against a common x axis, with shaded bands where given."""
    labels = [s.label for s in series]
    top = 20.0 + (16 if title else 0) + legend_height(labels)
    bottom = top + height
    xs = [v for s in series for v in s.x]
    ys = [v for s in series for v in [*s.y, *(s.band[0] if s.band else []), *(s.band[1] if s.band else [])]]
    x = Scale(*(xlim or _range(xs, xlog)), 60.0, WIDTH - 14, xlog)
    y = Scale(*(ylim or _range(ys, ylog)), bottom, top, ylog)
    body = [_text(WIDTH / 2, 14, title, "middle", 12, ' font-weight="bold"')] if title else []
    colors = [COLORS[(k if s.color is None else s.color) % len(COLORS)] for k, s in enumerate(series)]
    body += _legend(labels, 60.0, top - legend_height(labels) + 4, colors)
    body += _x_axis(x, top, bottom, xlabel) + _y_axis(y, 60.0, WIDTH - 14, ylabel)
    ok_x = (lambda v: np.isfinite(v) and (v > 0 or not xlog))
    ok_y = (lambda v: np.isfinite(v) and (v > 0 or not ylog))

    def inside(px: float, py: float) -> bool:
        return x.a - 1 <= px <= x.b + 1 and y.b - 1 <= py <= y.a + 1

    for g in guides:
        body.append(f'<path d="M{_f(x(g.x[0]))} {_f(y(g.y[0]))}L{_f(x(g.x[1]))} {_f(y(g.y[1]))}" stroke="#999" '
                    f'stroke-dasharray="4 3"><title>{escape(g.label)}</title></path>')
    for k, (s, color) in enumerate(zip(series, colors)):
        marks = [f'<g class="series" data-series="{k}" stroke="{color}" fill="{color}">']
        idx = [i for i in range(len(s.x)) if ok_x(s.x[i]) and ok_y(s.y[i])]
        if s.band is not None:
            lo, hi = s.band
            bi = [i for i in range(len(s.x)) if ok_x(s.x[i]) and ok_y(lo[i]) and ok_y(hi[i])]
            if len(bi) > 1:
                pts = [f"{_f(x(s.x[i]))},{_f(y(hi[i]))}" for i in bi] + \
                      [f"{_f(x(s.x[i]))},{_f(y(lo[i]))}" for i in reversed(bi)]
                marks.append(f'<polygon points="{" ".join(pts)}" fill-opacity="0.18" stroke="none"/>')
        if not s.points and len(idx) > 1:
            marks.append(f'<polyline points="{" ".join(f"{_f(x(s.x[i]))},{_f(y(s.y[i]))}" for i in idx)}" '
                         'fill="none" stroke-width="1.5"/>')
        for i in idx:
            px, py = x(s.x[i]), y(s.y[i])
            if not inside(px, py):
                continue
            hollow = bool(s.hollow[i]) if s.hollow is not None else False
            tip = f"{s.label}: x = {num(s.x[i])}, y = {num(s.y[i])}"
            if s.band is not None:
                tip += f" [{num(s.band[0][i])}, {num(s.band[1][i])}]"
            tip += (" (untrusted)" if hollow else "") + (f"; {s.notes[i]}" if s.notes else "")
            fill = ' fill="white"' if hollow else ""
            marks.append(f'<circle cx="{_f(px)}" cy="{_f(py)}" r="{3.2 if s.points else 2.5}"{fill}>'
                         f"<title>{escape(tip)}</title></circle>")
        body += marks + ["</g>"]
    return _svg(bottom + 42, body, title or ylabel)


def _color(v: float, lo: float, hi: float) -> str:
    """White to dark blue (viridis would need a table; one hue reads well for indices in [0, 1])."""
    if not np.isfinite(v):
        return "#eeeeee"
    t = min(max((v - lo) / ((hi - lo) or 1.0), 0.0), 1.0)
    r, g, b = (int(round(255 + (c - 255) * t)) for c in (8, 48, 107))
    return f"#{r:02x}{g:02x}{b:02x}"


@dataclass
class Heat:
    """Cell values of a heatmap, ``rows x cols``; ``marked`` cells (untrusted) get a red corner."""

    values: np.ndarray
    marked: np.ndarray | None = None


def heatmap(rows: Sequence[str], cols: Sequence[str], heat: Heat, label: str, title: str = "",
            vmin: float = 0.0, vmax: float = 1.0) -> str:
    """A table of coloured cells (values printed where the cells are wide enough), a colour bar
    labelled ``label``."""
    left = min(max(10 + 6.0 * max((len(r) for r in rows), default=4), 60.0), 0.45 * WIDTH)
    top = 22.0 + (16 if title else 0)
    label_h = min(6.0 * max((len(c) for c in cols), default=4), 140.0)
    cw = min((WIDTH - left - 70) / max(len(cols), 1), 60.0)
    ch = 18.0
    y0 = top + label_h
    height = y0 + ch * len(rows) + 24
    body = [_text(WIDTH / 2, 14, title, "middle", 12, ' font-weight="bold"')] if title else []
    for j, c in enumerate(cols):
        cx = left + (j + 0.5) * cw
        body.append(_text(cx + 3, y0 - 4, c, "start", 10, f' transform="rotate(-60 {_f(cx + 3)} {_f(y0 - 4)})"'))
    body.append('<g class="series" data-series="0">')
    for i, r in enumerate(rows):
        cy = y0 + i * ch
        body.append(_text(left - 5, cy + ch / 2 + 3, r, "end", 10))
        for j, c in enumerate(cols):
            v = float(heat.values[i, j])
            mark = bool(heat.marked[i, j]) if heat.marked is not None else False
            tip = f"{r}, {c}: {num(v)}" + (" (untrusted)" if mark else "")
            px = left + j * cw
            body.append(f'<rect x="{_f(px)}" y="{_f(cy)}" width="{_f(cw - 1)}" height="{_f(ch - 1)}" '
                        f'fill="{_color(v, vmin, vmax)}"><title>{escape(tip)}</title></rect>')
            dark = np.isfinite(v) and (v - vmin) / ((vmax - vmin) or 1) > 0.55
            if cw >= 26 and len(cols) <= 12 and np.isfinite(v):
                body.append(_text(px + cw / 2, cy + ch / 2 + 3, f"{v:.2f}", "middle", 9,
                                  ' fill="white" pointer-events="none"' if dark else ' pointer-events="none"'))
            if mark:     # a red corner: the value stays readable
                body.append(f'<path d="M{_f(px + cw - 9)} {_f(cy)}h8v8z" fill="#d62728" pointer-events="none"/>')
    body.append("</g>")
    bx = left + cw * len(cols) + 14
    steps = 10
    for k in range(steps):
        v = vmin + (vmax - vmin) * (steps - 1 - k) / (steps - 1)
        body.append(f'<rect x="{_f(bx)}" y="{_f(y0 + k * 12)}" width="12" height="12" fill="{_color(v, vmin, vmax)}"/>')
    body.append(_text(bx + 16, y0 + 9, num(vmax), size=9))
    body.append(_text(bx + 16, y0 + steps * 12, num(vmin), size=9))
    body.append(_text(bx, y0 + steps * 12 + 14, label, size=9))
    return _svg(max(height, y0 + steps * 12 + 24), body, title or label)
