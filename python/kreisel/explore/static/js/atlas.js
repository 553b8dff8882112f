// The atlas of play tops: the (alpha, gamma) plane painted by zone with its boundaries and
// the current top marked (a click picks a new alpha and gamma), and J_R(u) with the
// stationary motions at the current Jellett integral.
import uPlot from 'uplot';
import { clickIn, plotBox } from './canvas.js';
import { ticks } from './charts.js';

const ZONE_COLORS = ['#ffffff', '#d6e9f8', '#b4d4ee', '#fde2c4', '#fbd0a0', '#f9be7c', '#f6ab58',
  '#d9f0d3', '#b5e0ac'];
const ZONE_NAMES = { 1: 'Ia', 2: 'Ib', 3: 'IIa', 4: 'IIa', 5: 'IIa', 6: 'IIa', 7: 'IIb', 8: 'IIb' };
const PAD = { left: 48, right: 12, top: 12, bottom: 40 };

export class Atlas {
  constructor(canvas, jrElement, caption, onPick) {
    this.caption = caption;
    this.canvas = canvas;
    this.jrElement = jrElement;
    this.onPick = onPick;
    this.plane = null;
    this.current = null;
    this.jr = null;
    canvas.addEventListener('click', (e) => this.click(e));
  }

  setPlane(plane) {
    this.plane = plane;
    this.draw();
  }

  box() {
    return plotBox(this.canvas, PAD);
  }

  range() {
    const a = this.plane.alpha;
    const g = this.plane.gamma;
    return { a0: a[0], a1: a[a.length - 1], g0: g[0], g1: g[g.length - 1] };
  }

  toPixel(alpha, gamma) {
    const b = this.box();
    const r = this.range();
    return [b.x0 + ((alpha - r.a0) / (r.a1 - r.a0)) * b.w, b.y0 + (1 - (gamma - r.g0) / (r.g1 - r.g0)) * b.h];
  }

  fromPixel(px, py) {
    const b = this.box();
    const r = this.range();
    return [r.a0 + ((px - b.x0) / b.w) * (r.a1 - r.a0), r.g0 + (1 - (py - b.y0) / b.h) * (r.g1 - r.g0)];
  }

  draw() {
    if (!this.plane) return;
    const g = this.canvas.getContext('2d');
    const { width, height } = this.canvas;
    const b = this.box();
    g.clearRect(0, 0, width, height);
    const zones = this.plane.zones;
    const rows = zones.length;
    const cols = zones[0].length;
    const cw = b.w / cols;
    const ch = b.h / rows;
    for (let i = 0; i < rows; i++) {
      for (let j = 0; j < cols; j++) {
        g.fillStyle = ZONE_COLORS[zones[i][j]] || '#fff';
        g.fillRect(b.x0 + j * cw, b.y0 + (rows - 1 - i) * ch, cw + 0.6, ch + 0.6);
      }
    }
    g.save();
    g.beginPath();
    g.rect(b.x0, b.y0, b.w, b.h);
    g.clip();
    g.strokeStyle = '#33414f';
    g.lineWidth = 1.2;
    for (const curve of Object.values(this.plane.boundaries)) {
      g.beginPath();
      let on = false;
      curve.forEach((gamma, k) => {
        if (gamma === null) { on = false; return; }
        const [x, y] = this.toPixel(this.plane.alpha[k], gamma);
        if (on) g.lineTo(x, y); else g.moveTo(x, y);
        on = true;
      });
      g.stroke();
    }
    g.restore();
    g.strokeStyle = '#1d232b';
    g.strokeRect(b.x0, b.y0, b.w, b.h);
    g.fillStyle = '#1d232b';
    g.font = '12px sans-serif';
    const r = this.range();
    for (let k = 0; k <= 4; k++) {
      const a = r.a0 + ((r.a1 - r.a0) * k) / 4;
      const gm = r.g0 + ((r.g1 - r.g0) * k) / 4;
      const [xa] = this.toPixel(a, r.g0);
      const [, yg] = this.toPixel(r.a0, gm);
      g.fillText(a.toFixed(2), xa - 12, b.y0 + b.h + 15);
      g.fillText(gm.toFixed(2), 16, yg + 4);
    }
    g.fillText('α = s/ρ', b.x0 + b.w / 2 - 20, height - 6);
    g.save();
    g.translate(12, b.y0 + b.h / 2 + 70);
    g.rotate(-Math.PI / 2);
    g.fillText('γ = A/C', 0, 0);
    g.restore();
    if (this.current) {
      const [x, y] = this.toPixel(this.current.alpha, this.current.gamma);
      g.fillStyle = '#c0392b';
      g.strokeStyle = '#fff';
      g.lineWidth = 2;
      g.beginPath();
      g.arc(x, y, 6, 0, 2 * Math.PI);
      g.fill();
      g.stroke();
      g.fillStyle = '#1d232b';
      g.fillText(`zone ${this.current.zone} (${ZONE_NAMES[this.current.zone] || '?'})`, x + 9, y - 8);
    }
  }

  click(event) {
    if (!this.plane) return;
    const at = clickIn(this.canvas, event, this.box());
    if (!at) return;
    const [alpha, gamma] = this.fromPixel(...at);
    this.onPick(alpha, gamma);
  }

  // The atlas of the current run (null: not a play top).
  setTop(atlas) {
    this.current = atlas;
    this.draw();
    if (this.jr) { this.jr.destroy(); this.jr = null; }
    if (!atlas) return;
    // J_R(u) on the grid, with the stationary motions' u put in it (as points at |J|: J_R is
    // the |J| at which a regular precession at u exists, whatever the sense of the spin)
    const J = Math.abs(atlas.J);
    const rows = atlas.u.map((u, k) => [u, atlas.J_R[k], null]);
    for (const m of atlas.stationary) {
      const k = rows.findIndex(([u]) => u >= m.u);
      if (k >= 0 && rows[k][0] === m.u) rows[k][2] = J;
      else rows.splice(k < 0 ? rows.length : k, 0, [m.u, null, J]);
    }
    const data = [rows.map((r) => r[0]), rows.map((r) => r[1]), rows.map(() => J), rows.map((r) => r[2])];
    this.jr = new uPlot({
      width: 520, height: 380,
      scales: { x: { time: false } },
      axes: [{ label: 'u = cos θ' }, { label: 'J (kg m²/s)', size: 70, values: ticks }],
      legend: { live: false },
      series: [{}, { label: 'J_R(u)', stroke: '#1f77b4', width: 1.6, spanGaps: true },
        { label: `|J| = ${J.toPrecision(4)}`, stroke: '#7f8c8d', dash: [6, 4] },
        { label: 'stationary motions', stroke: '#c0392b', width: 0, points: { show: true, size: 10, fill: '#c0392b' } }],
    }, data, this.jrElement);
    const names = atlas.stationary.map((m) => `${m.kind} at u = ${m.u.toFixed(3)} (${m.stable ? 'stable' : 'unstable'})`);
    this.caption.textContent = `J_R(u) and the stationary motions at the top's |J| = ${J.toPrecision(4)} kg m²/s: ${names.join('; ') || 'none'}.`;
  }
}
