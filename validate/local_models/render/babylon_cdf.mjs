// Babylon.js's CDF irradiance (Babylon PR 16010 "Use CDF for irradiance prefiltering", PR 16247 "Make prefiltering
// using CDF default to supersample"): an HDRCubeTexture built with prefilterIrradianceOnLoad = prefilterUsingCdf =
// true and generateHarmonics = false. On load Babylon converts the panorama to a cube of `size` (its
// PanoramaToCubeMapTools, supersampled by round(W/4/size)² samples per texel when `supersample`), builds the CDF maps
// of that cube (Rendering/iblCdfGenerator.js) and importance-samples them into an irradiance cube
// (Materials/Textures/Filtering/hdrIrradianceFiltering.js, 4096 samples per texel), which the PBR material reads as
// its irradiance map (USEIRRADIANCEMAP). No radiance prefilter (prefilterOnLoad false): the scenes using this are
// Lambertian (metallicF0Factor 0), so only the irradiance term lights them.
//
// supersample 'shipped': Babylon 9.35 as shipped — the constructor forces `_supersample = supersample ||
// prefilterUsingCdf` (PR 16247). supersample 'pre16247': the code before that PR (`_supersample = supersample`,
// false by default), restored by resetting the field right after construction: the field is read only in the load
// callback (envCubeTexture.pure.js _loadTexture → _getCubeMapTextureDataAsync(buffer, size, this._supersample)),
// which runs after the panorama has been fetched, i.e. after this function returns.
//
// Where the energy goes under a compact sun (measured; docs/experiments/renders.md, "Babylon PR 16247";
// scripts/diagnose_renders/): before any CDF. PanoramaToCubeMapTools.CreateCubemapTexture point-samples the panorama
// (nearest texel by Math.round) on a lattice of round(W/4/size) corner-aligned sub-samples per texel axis — W/4 = 256
// points per face edge at every size 64–256 (the same points), about one per panorama texel — so a sun of a few
// texels aliases against it; IblCdfGenerator then point-samples the cube (bilinear) on a 4·size × 2·size equirect
// grid, a second alias. Neither is a clamp (the ratios are scale-invariant), nor the 4096 importance samples.
export function cdfCubeTexture(BABYLON, url, scene, size, supersample) {
  // a query string per variant: Babylon's texture cache matches cube textures by url (not size), and the static
  // server ignores the query
  const u = `${url}?cdf=${size}&ss=${supersample}`;
  const tex = new BABYLON.HDRCubeTexture(u, scene, size, false, false, false, false, null, null, false, true, true);
  if (supersample === 'pre16247') tex._supersample = false;
  return tex;
}

export function cdfKey(env, opts, size) {
  return `${env.key}|cdf${size}|${opts.supersample}`;
}

// What the page reports of the CDF texture: the irradiance cube it made, the cube size, whether it supersampled.
export function cdfInfo(tex) {
  const irr = tex && tex.irradianceTexture;
  const dir = irr && irr._dominantDirection;
  return {irradiance: !!irr, irradianceSize: irr ? irr.getSize().width : 0, cubeSize: tex ? tex.getSize().width : 0,
          supersample: tex ? !!tex._supersample : null, dominantDirection: dir ? [dir.x, dir.y, dir.z] : null};
}
