// The 3D lab's scenes: a source — a preset `{ preset, grid }`, or a file
// `{ name, bytes, files: [[name, bytes]…], emitFromKa }` with the other files the user gave
// (an OBJ's .mtl libraries, a .gltf's buffers) — as a `Lab3` of the 3D module. The page and
// its worker both hold the scene.
export function labOf(Lab3, s) {
  if (s.preset) return Lab3.preset(s.preset, s.grid);
  const sizes = Uint32Array.from(s.files, ([, b]) => b.length);
  const all = new Uint8Array(sizes.reduce((a, b) => a + b, 0));
  let at = 0;
  for (const [, b] of s.files) {
    all.set(b, at);
    at += b.length;
  }
  return Lab3.fromFile(s.name, s.bytes, s.files.map(([n]) => n), sizes, all, s.emitFromKa);
}

// Patches: above this the I_ij heat map is not drawn (the matrix is n² doubles, 8 MiB at 1024).
export const HEAT_MAP_LIMIT = 1024;
