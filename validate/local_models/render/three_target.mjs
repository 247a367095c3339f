// One frame of a three.js scene into a float render target, read back exactly: RGBA float32, row 0 = bottom
// (WebGL's readPixels order), alpha = coverage (cleared to 0). Shared by three_render.mjs (the suite's scene JSON)
// and three_gltf.mjs (the exported files through GLTFLoader).
import * as THREE from 'three';

export function renderFloat(r, scene, cam, width, height) {
  const target = new THREE.WebGLRenderTarget(width, height, {type: THREE.FloatType, format: THREE.RGBAFormat,
    colorSpace: THREE.LinearSRGBColorSpace, depthBuffer: true, minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter});
  r.setRenderTarget(target);
  r.setClearColor(0x000000, 0); r.clear();
  const t0 = performance.now();
  r.render(scene, cam);
  const out = new Float32Array(width * height * 4);
  r.readRenderTargetPixels(target, 0, 0, width, height, out);
  const frame_ms = performance.now() - t0;
  r.setRenderTarget(null);
  target.dispose();
  return {out, frame_ms};
}
