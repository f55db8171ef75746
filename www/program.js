// The Program view (issue 19, step 2; issue 32): the finishing flank pass of both walls as a CL
// file (the format the Error budget view reads) and as G-code in the chosen controller's dialect,
// in the machine axes of the chosen chain or in its tool-centre-point mode.
// Every number and both files come from the core's `partProgram` export (src/program/); this file
// only reads the view's inputs, draws and offers the downloads. Machine, L0 and B branch are the
// page's settings (left).
import { download } from './export.js';
import { h, table } from './ui.js';

const um = (v) => ({ text: (v * 1000).toFixed(3), num: true, value: v * 1000 });

/** Sets up the view in `root`. ctx = {call, st, withProgress}. Returns {refresh}; the view
 *  computes when its tab is chosen and when its inputs or the machine settings change. */
export function setupProgram(root, ctx) {
  let seq = 0;
  let last = null;
  const input = (id, label, attrs) => h('label', { for: id }, label, ' ', h('input', { id, type: 'number', ...attrs }));
  const controls = h('div', { class: 'bar', id: 'program-controls' },
    input('program-tolerance', 'Chord tolerance (µm)', { min: 0.01, max: 1000, step: 0.1, value: 1 }),
    input('program-feed', 'Feed (mm/min)', { min: 1, step: 10, value: 1000 }),
    h('label', { for: 'program-dialect', title: 'The controller the G-code is written for: its start block, tool call, length compensation, machine-coordinate retract, comments and word lengths (8 significant digits at most).' }, 'Controller ',
      h('select', { id: 'program-dialect' }, h('option', { value: 'iso' }, 'iso'))),
    h('label', { for: 'program-tcp', title: 'Tool-centre-point mode (Fanuc G43.4, SINUMERIK TRAORI, Heidenhain FUNCTION TCPM): the tip in the part frame and the rotary angles, the feed held at the tip by the controller. Off: machine axes, the pass in inverse-time feed (G93; Klartext: per-block feeds).' }, h('input', { id: 'program-tcp', type: 'checkbox' }), ' Tool-centre-point mode'));
  const downloads = h('div', { class: 'bar' },
    h('button', { type: 'button', id: 'program-cl', onclick: () => last && download('testpiece-finishing.apt', last.cl, 'text/plain') }, 'Download CL file (APT)'),
    h('button', { type: 'button', id: 'program-gcode', onclick: () => last && download('testpiece-finishing.nc', last.gcode, 'text/plain') }, 'Download G-code'));
  const out = h('div', { id: 'program-out' });
  root.append(h('h2', {}, 'Part program: the finishing flank pass (roughing not included)'),
    h('p', {}, 'Surface A then B, each in increasing u, a flat end mill of diameter 20 mm with its tip on the flank path of paper 000 eq. 2. Positions are placed so that the scallop between two positions, the chord of the tip path and the controller\'s linear interpolation of the machine axes all stay within the tolerance; the axis values follow the chosen machine and B branch through the vertical zone, as the analysis assumes. Around the cut: Z to the machine\'s home first, tool call with length compensation, spindle and coolant; per surface the rotary axes alone at a safe height, then X Y, then down to 3 mm clear of the part, feed along the tool axis into the pass and out of it until the tool clears the part; Z home, spindle and coolant off, end. The CL file (with RAPID positioning) is read back by the Error budget view.'),
    controls, downloads, out);
  const value = (id) => parseFloat(root.querySelector(`#${id}`).value);

  async function refresh() {
    const s = ctx.st.settings;
    const dialect = root.querySelector('#program-dialect').value;
    const tcp = root.querySelector('#program-tcp').checked;
    const options = { machine: s.machine, l0: s.l0, branch: s.branch, tolerance: value('program-tolerance') / 1000, feed: value('program-feed'), dialect, tcp };
    const mine = ++seq;
    try {
      const r = await ctx.withProgress('Making the part program…', () => ctx.call('partProgram', options));
      if (mine !== seq) return;
      last = r;
      dialects(root, r);
      render(out, r);
    } catch (e) {
      if (mine !== seq) return;
      last = null;
      out.textContent = '';
      out.append(h('pre', { class: 'error', id: 'program-error' }, e.message));
    }
  }
  controls.addEventListener('change', refresh);
  document.getElementById('tab-program')?.addEventListener('click', () => { if (!last) refresh(); });
  for (const id of ['machine', 'branch', 'l0']) {
    document.getElementById(id)?.addEventListener('change', () => { if (root.hidden) last = null; else refresh(); });
  }
  return { refresh };
}

// The controllers offered and whether each has a TCP mode, as the core lists them.
function dialects(root, r) {
  const sel = root.querySelector('#program-dialect');
  const chosen = r.settings.dialect;
  if (sel.options.length !== r.dialects.length) {
    sel.textContent = '';
    for (const d of r.dialects) sel.append(h('option', { value: d.id }, d.name));
  }
  sel.value = chosen;
  const tcp = root.querySelector('#program-tcp');
  tcp.disabled = !r.dialects.find((d) => d.id === chosen)?.tcp;
  if (tcp.disabled) tcp.checked = false;
}

function render(out, r) {
  out.textContent = '';
  out.dataset.positions = String(r.passes.reduce((n, p) => n + p.positions, 0));
  out.append(h('pre', { id: 'program-header' }, r.header));
  out.append(table('program-passes', `The passes (${r.machine}; tolerance ${(r.settings.tolerance * 1000).toFixed(3)} µm)`,
    ['surface', 'positions', 'in the vertical zone', 'largest step (mm)', 'largest scallop (µm)', 'largest interval error (µm)'],
    r.passes.map((p) => [p.surface, { text: p.positions, num: true }, { text: p.singular_positions, num: true },
      { text: p.max_step.toFixed(4), num: true, value: p.max_step }, um(p.max_scallop), um(p.max_interval_error)])));
  out.append(h('p', { id: 'program-words' }, `G-code: safe height Z ${r.z_safe.toFixed(3)} mm (machine); axis words rounded to 8 significant digits move the tool path by at most ${(r.rounding_bound * 1000).toFixed(3)} µm.`));
  out.append(h('ul', { id: 'program-notes' }, r.notes.map((n) => h('li', {}, n))));
}
