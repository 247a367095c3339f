// A Babylon.js scene that renders linear radiance, shared by the hand-built page (babylon_render.mjs) and the loader
// page (babylon_gltf.mjs): right-handed (glTF's frame), transparent black clear colour, and image processing "applied
// by a post process" with tone mapping off, exposure and contrast 1 — the PBR shader then skips its own tone mapping
// and its final toGammaSpace (measured: without this the target held radiance^(1/2.2)); no post process is attached
// to the render target, so nothing applies it.
import * as BABYLON from '../../../node_modules/@babylonjs/core/index.js';

export function linearScene(eng) {
  const scene = new BABYLON.Scene(eng);
  scene.useRightHandedSystem = true;
  scene.imageProcessingConfiguration.applyByPostProcess = true;
  scene.imageProcessingConfiguration.toneMappingEnabled = false;
  scene.imageProcessingConfiguration.exposure = 1.0;
  scene.imageProcessingConfiguration.contrast = 1.0;
  scene.clearColor = new BABYLON.Color4(0, 0, 0, 0);
  return scene;
}
