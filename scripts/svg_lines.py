"""A small SVG line plot for the scaling scripts (no plotting library on a fresh machine):
series of (x, y) points on linear axes, ticks at the x values, a legend in the corner."""


def line_plot(path, series, xlabel, ylabel, width=640, height=400, pad=60):
    """series: list of (label, colour, [(x, y), ...]); writes the SVG to path."""
    xs = sorted({x for _, _, pts in series for x, _ in pts})
    top = max((y for _, _, pts in series for _, y in pts), default=0) * 1.1 or 1.0

    def px(v):
        return pad + (width - 2 * pad) * (v - min(xs)) / max(1, max(xs) - min(xs))

    def py(v):
        return height - pad - (height - 2 * pad) * v / top

    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="sans-serif" font-size="12">',
             f'<rect width="{width}" height="{height}" fill="white"/>',
             f'<line x1="{pad}" y1="{height - pad}" x2="{width - pad}" y2="{height - pad}" stroke="black"/>',
             f'<line x1="{pad}" y1="{pad}" x2="{pad}" y2="{height - pad}" stroke="black"/>',
             f'<text x="{width / 2}" y="{height - 20}" text-anchor="middle">{xlabel}</text>',
             f'<text x="15" y="{height / 2}" transform="rotate(-90 15 {height / 2})" text-anchor="middle">{ylabel}</text>']
    for v in xs:
        parts.append(f'<text x="{px(v):.1f}" y="{height - pad + 16}" text-anchor="middle">{v}</text>')
    for frac in (0, 0.25, 0.5, 0.75, 1.0):
        parts.append(f'<text x="{pad - 6}" y="{py(top * frac) + 4:.1f}" text-anchor="end">{top * frac:.0f}</text>')
    for i, (label, colour, pts) in enumerate(series):
        pts = sorted(pts)
        parts.append('<polyline points="{}" fill="none" stroke="{}" stroke-width="2"/>'.format(
            " ".join(f"{px(x):.1f},{py(y):.1f}" for x, y in pts), colour))
        for x, y in pts:
            parts.append(f'<circle cx="{px(x):.1f}" cy="{py(y):.1f}" r="3" fill="{colour}"/>')
        parts.append(f'<text x="{pad + 10}" y="{pad + 14 + 16 * i}" fill="{colour}">{label}</text>')
    parts.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(parts))
