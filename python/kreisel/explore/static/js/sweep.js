import { clickIn, plotBox } from './canvas.js';

// The sweep viewer: a summary of a sweep store as a colour map over its first two swept
// parameters; a click on a cell asks for that run.

const PAD = { left: 70, right: 90, top: 14, bottom: 46 };
// viridis, five stops
const STOPS = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];

function colour(x) {
  const s = Math.min(Math.max(x, 0), 1) * (STOPS.length - 1);
  const k = Math.min(Math.floor(s), STOPS.length - 2);
  const f = s - k;
  const c = STOPS[k].map((v, i) => Math.round(v + f * (STOPS[k + 1][i] - v)));
  return `rgb(${c[0]},${c[1]},${c[2]})`;
}

// the readout's numbers: 4 significant digits
const read = (v) => String(Number(v.toPrecision(4)));
const fmt = (v) => (Math.abs(v) >= 1e4 || (Math.abs(v) < 1e-2 && v !== 0) ? v.toExponential(2) : v.toPrecision(3));

export class SweepMap {
  constructor(canvas, onCell, readout) {
    this.canvas = canvas;
    this.onCell = onCell;
    this.readout = readout;
    this.view = null;
    this.picked = null;
    canvas.addEventListener('click', (e) => this.click(e));
    canvas.addEventListener('mousemove', (e) => this.hover(e));
    canvas.addEventListener('mouseleave', () => { this.readout.textContent = ''; });
  }

  // The cell [i, j] under the mouse, or null.
  cellAt(event) {
    if (!this.view) return null;
    const b = this.box();
    const at = clickIn(this.canvas, event, b);
    if (!at) return null;
    const [px, py] = at;
    const { rows, cols } = this.shape();
    const j = Math.min(Math.floor(((px - b.x0) / b.w) * cols), cols - 1);
    const i = rows - 1 - Math.min(Math.floor(((py - b.y0) / b.h) * rows), rows - 1);
    return [i, j];
  }

  // The readout of the cell under the mouse: its swept values and its summary.
  hover(event) {
    const cell = this.cellAt(event);
    if (!cell) {
      this.readout.textContent = '';
      return;
    }
    const [i, j] = cell;
    const [dy, dx] = this.view.dims;
    const at = [`${dy} = ${read(this.view.coords[dy][i])}`];
    if (dx) at.push(`${dx} = ${read(this.view.coords[dx][j])}`);
    const v = this.view.values[i][j];
    const unit = this.view.units ? ` ${this.view.units}` : '';
    this.readout.textContent = `${at.join(', ')}: ${this.view.var} = ${v === null ? 'NaN' : read(v) + unit}`;
    this.readout.dataset.cell = JSON.stringify(cell);
  }

  // rows: the first swept parameter (bottom to top); columns: the second (or one column)
  shape() {
    const v = this.view.values;
    return { rows: v.length, cols: v[0].length };
  }

  box() {
    return plotBox(this.canvas, PAD);
  }

  setView(view) {
    this.view = view;
    this.picked = null;
    this.draw();
  }

  draw() {
    const g = this.canvas.getContext('2d');
    const { width, height } = this.canvas;
    g.clearRect(0, 0, width, height);
    if (!this.view) return;
    const { rows, cols } = this.shape();
    const b = this.box();
    const flat = this.view.values.flat().filter((v) => v !== null);
    const lo = Math.min(...flat);
    const hi = Math.max(...flat);
    const cw = b.w / cols;
    const ch = b.h / rows;
    for (let i = 0; i < rows; i++) {
      for (let j = 0; j < cols; j++) {
        const v = this.view.values[i][j];
        g.fillStyle = v === null ? '#bdbdbd' : colour(hi > lo ? (v - lo) / (hi - lo) : 0.5);
        g.fillRect(b.x0 + j * cw, b.y0 + (rows - 1 - i) * ch, cw + 0.5, ch + 0.5);
      }
    }
    if (this.picked) {
      const [i, j] = this.picked;
      g.strokeStyle = '#e74c3c';
      g.lineWidth = 2.5;
      g.strokeRect(b.x0 + j * cw + 1, b.y0 + (rows - 1 - i) * ch + 1, cw - 2, ch - 2);
    }
    g.fillStyle = '#1d232b';
    g.font = '12px sans-serif';
    const [dy, dx] = this.view.dims;
    const ys = this.view.coords[dy];
    const ticks = (n) => [...new Set([0, Math.floor((n - 1) / 2), n - 1])];
    for (const i of ticks(rows)) g.fillText(fmt(ys[i]), 4, b.y0 + (rows - 1 - i + 0.5) * ch + 4);
    if (dx) {
      const xs = this.view.coords[dx];
      for (const j of ticks(cols)) g.fillText(fmt(xs[j]), b.x0 + (j + 0.5) * cw - 14, b.y0 + b.h + 15);
      g.fillText(dx, b.x0 + b.w / 2 - 10, height - 8);
    }
    g.save();
    g.translate(12, b.y0 + b.h / 2 + 30);
    g.rotate(-Math.PI / 2);
    g.fillText(dy, 0, 0);
    g.restore();
    // the colour bar
    const bx = width - PAD.right + 14;
    for (let k = 0; k < b.h; k++) {
      g.fillStyle = colour(1 - k / b.h);
      g.fillRect(bx, b.y0 + k, 16, 1.5);
    }
    g.fillStyle = '#1d232b';
    g.fillText(fmt(hi), bx + 20, b.y0 + 10);
    g.fillText(fmt(lo), bx + 20, b.y0 + b.h);
    g.fillText(this.view.var, bx - 6, b.y0 + b.h + 28);
  }

  click(event) {
    const cell = this.cellAt(event);
    if (!cell) return;
    this.picked = cell;
    this.draw();
    this.onCell(this.view.dims.length > 1 ? cell : [cell[0]]);
  }
}
