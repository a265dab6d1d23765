// sceneinfo demo: the page draws, Rust computes (all numbers come from measureFlat).
import init, { measureFlat } from './pkg/sceneinfo_wasm.js';

// Equilateral triangle, counter-clockwise (so every segment faces inwards), 10 patches a side.
function triangleFlat() {
  const v = [[0, 0], [1, 0], [0.5, Math.sqrt(3) / 2]];
  const lines = ['# equilateral triangle, 10 patches per side'];
  for (let k = 0; k < 3; k++) {
    const [a, b] = [v[k], v[(k + 1) % 3]];
    lines.push(`seg ${a[0]} ${a[1]} ${b[0]} ${b[1]} 10`);
  }
  return lines.join('\n') + '\n';
}

// Formats one JSON value for the table.
function format(value) {
  if (typeof value !== 'number' || Number.isInteger(value)) return JSON.stringify(value);
  return value === 0 || Math.abs(value) >= 1e-3 ? value.toFixed(6) : value.toExponential(3);
}

// Appends one row per measure to `table`; nested objects become `outer.inner` rows.
function addRows(table, object, prefix) {
  for (const [key, value] of Object.entries(object)) {
    const name = prefix + key;
    if (value !== null && typeof value === 'object' && !Array.isArray(value)) {
      addRows(table, value, `${name}.`);
      continue;
    }
    const row = table.insertRow();
    row.insertCell().textContent = name;
    const cell = row.insertCell();
    cell.className = 'num';
    cell.id = `m_${name.replaceAll('.', '_')}`;
    cell.textContent = format(value);
  }
}

// Measures the textarea's scene: every measure in the table, or the error message.
function measureUserScene() {
  const error = document.getElementById('error');
  const table = document.getElementById('measures');
  table.replaceChildren();
  error.textContent = '';
  try {
    addRows(table, JSON.parse(measureFlat(document.getElementById('scene').value)), '');
  } catch (e) {
    error.textContent = e instanceof Error ? e.message : String(e);
  }
}

async function main() {
  await init();
  const text = triangleFlat();
  const m = JSON.parse(measureFlat(text));
  document.getElementById('h_s').textContent = m.h_s.toFixed(3);
  document.getElementById('i_s').textContent = m.i_s.toFixed(3);

  const scene = document.getElementById('scene');
  scene.value = text;
  const button = document.getElementById('measure');
  button.addEventListener('click', measureUserScene);
  button.disabled = false;
  measureUserScene();
  document.title = 'sceneinfo ready';
}

main().catch((e) => {
  const message = e instanceof Error ? e.message : String(e);
  document.title = `sceneinfo error: ${message}`;
  document.getElementById('error').textContent = message;
});
