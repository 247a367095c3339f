// Loaded by Babylon's EXR decoder as ExrLoaderGlobalConfiguration.FFLATEUrl (babylon_gltf.mjs): window.fflate is already
// three.js's copy of fflate, imported by the page, so this classic script has nothing left to do.
