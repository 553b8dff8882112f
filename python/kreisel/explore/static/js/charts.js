// The charts under the 3D view (uPlot), one per quantity, sharing the time axis; a cursor on
// each follows the time slider.
import uPlot from 'uplot';

// tick labels that stay readable for the small numbers of small tops
export function tick(v) {
  if (v === 0 || v === null) return v === 0 ? '0' : '';
  const a = Math.abs(v);
  return a < 1e-3 || a >= 1e5 ? v.toExponential(1) : String(Number(v.toPrecision(4)));
}
export const ticks = (u, values) => values.map(tick);

const COLORS = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#8c564b', '#e377c2'];

function layout(run) {
  if (run.kind === 'play') {
    return [
      { title: 'u = cos θ (1: upright, G above the tip)', keys: [['u', 'u']] },
      { title: 'contact mode', keys: [['mode', 'mode']], modes: run.modes },
      ...(run.contacts && run.contacts.parts.length ? [{
        // one track per part, each a little above the last where two share a state
        title: "each part's contact state",
        keys: run.contacts.parts.map((name, k) => [`part_state_${k}`, name]),
        modes: run.contacts.states,
        offset: 0.12,
        legend: true,
      }] : []),
      { title: 'normal force (N)', keys: [['normal_force', 'N']] },
      { title: 'energy and its parts (J)', keys: [['energy', 'total'], ['energy_translation', 'translation'],
        ['energy_rotation', 'rotation'], ['energy_potential', 'potential'], ['dissipated', 'dissipated']] },
      { title: "Jellett's integral J (kg m²/s)", keys: [['jellett', 'J']] },
    ];
  }
  const out = [
    { title: 'u = cos θ', keys: [['u', 'u']] },
    { title: 'energy and its parts (J)', keys: [['energy', 'total'], ['kinetic', 'kinetic'], ['potential', 'potential']] },
    { title: 'invariants: angular momentum (kg m²/s)', keys: [['Mz', 'Mz'], ['M3', 'M3']].filter(([k]) => k in run.series) },
  ];
  if ('kovalevskaya' in run.series) out.push({ title: "Kovalevskaya's integral", keys: [['kovalevskaya', 'K']] });
  if ('balance' in run.series) {
    // a moving or damped pivot: the energy balance replaces the integrals
    out[2] = { title: 'energy balance (J): E + dissipated − work by the pivot is constant',
      keys: [['work_by_pivot', 'work by the pivot'], ['dissipated', 'dissipated'], ['balance', 'E + D − W']] };
  }
  return out;
}

export class Charts {
  constructor(element) {
    this.element = element;
    this.plots = [];
    new ResizeObserver(() => this.resize()).observe(element);
  }

  width() {
    const w = this.element.clientWidth || 900;
    return Math.max(380, Math.floor(w / Math.max(1, Math.floor(w / 430))) - 8);
  }

  setRun(run) {
    for (const p of this.plots) p.plot.destroy();
    this.element.innerHTML = '';
    this.plots = [];
    for (const spec of layout(run)) {
      const box = document.createElement('div');
      box.className = 'chart';
      const h = document.createElement('h3');
      h.textContent = spec.title;
      box.appendChild(h);
      this.element.appendChild(box);
      const series = [{}];
      spec.keys.forEach(([, label], k) => series.push({ label, stroke: COLORS[k % COLORS.length], width: 1.4 }));
      const axes = [{ label: 't (s)' }, { values: ticks, size: 60 }];
      const scales = { x: { time: false } };
      if (spec.modes) {
        series[1].paths = uPlot.paths.stepped({ align: 1 });
        axes[1] = { splits: () => spec.modes.map((_, k) => k), values: (u, ticks) => ticks.map((k) => spec.modes[k] ?? ''), size: 60 };
        scales.y = { range: [-0.3, spec.modes.length - 0.7] };
      }
      if (spec.modes && spec.keys.length > 1) {
        spec.keys.forEach((_, k) => { series[k + 1].paths = uPlot.paths.stepped({ align: 1 }); series[k + 1].width = 2.5; });
        scales.y = { range: [-0.3, spec.modes.length - 0.7 + spec.offset * spec.keys.length] };
      }
      const shift = (values, k) => (spec.offset ? values.map((v) => (v === null ? null : v + spec.offset * k)) : values);
      const data = [run.t, ...spec.keys.map(([key], k) => shift(run.series[key], k))];
      const plot = new uPlot({ width: this.width(), height: 170, series, axes, scales,
        legend: { show: spec.keys.length > 1 || !!spec.legend, live: false }, cursor: { drag: { x: true, y: false } } }, data, box);
      const cursor = document.createElement('div');
      cursor.className = 'cursor';
      plot.over.appendChild(cursor);
      plot.root.dataset.chart = spec.keys[0][0];
      this.plots.push({ plot, cursor });
    }
  }

  resize() {
    for (const { plot } of this.plots) plot.setSize({ width: this.width(), height: 170 });
  }

  // The cursor of every chart at time t (s).
  setCursor(t) {
    for (const { plot, cursor } of this.plots) {
      const x = plot.valToPos(t, 'x');
      // a transform moves the cursor's own layer: the chart under it is not painted again
      cursor.style.transform = `translateX(${x}px)`;
      cursor.dataset.t = String(t);
    }
  }
}
