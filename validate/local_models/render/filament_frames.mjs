// Filament's frames on an 8-bit canvas, shared by the hand-built page (filament_render.mjs) and the gltfio page
// (filament_gltf.mjs): the frame loop, the RGBA8 readback (row 0 = bottom) and the auto exposure.
//
// Filament's exposure (Exposure.cpp; Lagarde & de Rousiers 2014, "Moving Frostbite to PBR", §4.6):
// e = 1/(1.2·2^EV100), EV100 = log2(N²/t · 100/S); with N = 1, t = 1.2 s: e = S/100, so ISO S = 100·e. (Measured:
// Camera.setExposureDirect(x) of this build sets S = 100/x, i.e. e = 1/x, and the image scales as 1/x; it is not used.)
//
// Auto exposure from Filament's own frames (no reference involved): start at e = 1/8 (radiance 8 → full scale),
// divide by 8 while the brightest channel saturates, then scale e so that it reads FILL_LSB (the image fills the
// 8-bit range, the quantisation step relative to the peak is smallest).
export const FILL_LSB = 250;

export function setExposure(cam, e) { cam.setExposure(1.0, 1.2, 100.0 * e); }

const frame = () => new Promise((r) => requestAnimationFrame(r));

// `frames` frames of `view` drawn (at most 200 animation frames tried); returns how many were drawn.
export async function drawFrames(renderer, swapChain, view, eng, frames) {
  let drawn = 0;
  for (let k = 0; k < 200 && drawn < frames; k++) {
    await frame();
    if (renderer.beginFrame(swapChain)) { renderer.renderView(view); renderer.endFrame(); drawn++; }
    eng.execute();
  }
  return drawn;
}

export function readRgba8(gl, width, height) {
  const px = new Uint8Array(width * height * 4);
  gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, px);
  return px;
}

export function maxColour(px) { let m = 0; for (let i = 0; i < px.length; i++) if ((i & 3) !== 3 && px[i] > m) m = px[i]; return m; }

// The auto exposure above (`fixed`: an exposure to use as given); {exposure, px, drawn}.
export async function exposeAndRead({renderer, swapChain, gl}, cam, view, eng, width, height, fixed) {
  let exposure = fixed || 0.125, px = null, drawn = 0;
  for (let k = 0; k < 8; k++) {
    setExposure(cam, exposure);
    drawn += await drawFrames(renderer, swapChain, view, eng, 2);
    px = readRgba8(gl, width, height);
    const m = maxColour(px);
    if (fixed) break;
    if (m >= 255) { exposure /= 8; continue; }
    if (m === 0) throw new Error('filament: black image');
    exposure *= FILL_LSB / m;
    setExposure(cam, exposure);
    drawn += await drawFrames(renderer, swapChain, view, eng, 2);
    px = readRgba8(gl, width, height);
    break;
  }
  return {exposure, px, drawn};
}
