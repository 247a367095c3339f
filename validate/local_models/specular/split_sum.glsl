// validate: family=specular
// validate: name=glsl_split_sum_ggx
// validate: brdf=ggx
// validate: description=GLSL transcription of split_sum_ggx (conductor): P_alpha(r) (F0 A(mu_v, alpha) + B(mu_v, alpha)), the harness's GGX-prefiltered cube map and DFG table
// validate: source=Karis 2013, Real Shading in Unreal Engine 4, eq. 7 (split sum); Lagarde & de Rousiers 2014 §4.9 (DFG table)
//
// As validate.local_models.specular.split_sum.shade_split_sum: r = 2(n.v)n - v, mu_v = clamp(n.v, 0, 1);
// prefiltered_radiance and env_brdf are the harness's float32 transcriptions of CubeMap.lookup and
// DFGTable.lookup on the same map (split_sum.prefilter_ggx_cube) and table (split_sum.default_dfg_table).
vec3 specular(vec3 n, vec3 v) {
    float nv = dot(n, v);
    vec2 ab = env_brdf(clamp(nv, 0.0, 1.0), u_alpha);
    return prefiltered_radiance(2.0 * nv * n - v) * (u_f0 * ab.x + ab.y);
}
