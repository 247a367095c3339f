// Shared by the engine pages: base64 <-> Float32Array, and the scene JSON of validate.scenes.render_scenes.
export function b64ToF32(s) {
  const b = atob(s); const u = new Uint8Array(b.length);
  for (let i = 0; i < b.length; i++) u[i] = b.charCodeAt(i);
  return new Float32Array(u.buffer);
}
export function f32ToB64(f) {
  const u = new Uint8Array(f.buffer, f.byteOffset, f.byteLength); let s = '';
  for (let i = 0; i < u.length; i += 0x8000) s += String.fromCharCode.apply(null, u.subarray(i, i + 0x8000));
  return btoa(s);
}
// Equirect texels of the environment, RGBA float32, row 0 = TOP (elevation +90 deg), as the scene sends them
// (a constant environment arrives as a small constant panorama, so both engines take their own prefilter path).
export function environmentTexels(env) {
  return {width: env.width, height: env.height, data: b64ToF32(env.data)};
}
