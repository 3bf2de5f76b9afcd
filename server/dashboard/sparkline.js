// A sparkline: one SVG polyline per series, drawn by hand (no library), on a shared scale from 0
// to the largest value shown.
const SVG = 'http://www.w3.org/2000/svg';
const WIDTH = 100;
const HEIGHT = 20;

/// An <svg> for `series` ({name, values}; name is its CSS class), with the number of points as
/// data-points and a title naming the last values.
export function sparkline(series, label) {
  const svg = document.createElementNS(SVG, 'svg');
  svg.setAttribute('viewBox', `0 0 ${WIDTH} ${HEIGHT}`);
  svg.setAttribute('preserveAspectRatio', 'none');
  svg.setAttribute('role', 'img');
  svg.setAttribute('aria-label', label);
  const count = Math.max(...series.map((s) => s.values.length));
  const top = Math.max(1e-6, ...series.flatMap((s) => s.values));
  for (const { name, values } of series) {
    const line = document.createElementNS(SVG, 'polyline');
    line.setAttribute('class', name);
    const step = count > 1 ? WIDTH / (count - 1) : 0;
    const offset = count - values.length;
    line.setAttribute('points', values
      .map((v, i) => `${((offset + i) * step).toFixed(1)},${(HEIGHT - (v / top) * (HEIGHT - 1) - 0.5).toFixed(1)}`)
      .join(' '));
    svg.append(line);
  }
  svg.dataset.points = String(count);
  return svg;
}
