// validate: family=specular
// validate: name=my_env_brdf_approx
// validate: brdf=ggx
// validate: description=split sum with Karis's analytic environment BRDF (mobile EnvBRDFApprox) in place of the DFG table
// validate: source=B. Karis, "Physically Based Shading on Mobile", Unreal Engine blog, 2014 (EnvBRDFApprox, after Lazarov 2013)
//
// A plug-in example for `python -m validate run ibl --plugin examples/my_specular.glsl`: the harness's GGX-
// prefiltered cube map at r (prefiltered_radiance) times F0 A + B from Karis's fit, whose "Roughness" is UE4's
// roughness = sqrt(alpha) (validate's alpha is Mitsuba's).
vec3 specular(vec3 n, vec3 v) {
    float nv = dot(n, v);
    float roughness = sqrt(u_alpha);
    vec4 c0 = vec4(-1.0, -0.0275, -0.572, 0.022);
    vec4 c1 = vec4(1.0, 0.0425, 1.04, -0.04);
    vec4 r = roughness * c0 + c1;
    float a004 = min(r.x * r.x, exp2(-9.28 * clamp(nv, 0.0, 1.0))) * r.x + r.y;
    vec2 ab = vec2(-1.04, 1.04) * a004 + r.zw;
    return prefiltered_radiance(2.0 * nv * n - v) * (u_f0 * ab.x + ab.y);
}
