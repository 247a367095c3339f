// A complete GLSL technique: the modified Phong BRDF (Lafortune & Willems 1994), written as a shader.
//
//   python -m validate run brdfs --plugin examples/my_brdf.glsl    # a row in the brdfs report
//   python -m validate list --plugin examples/my_brdf.glsl         # listed with its family
//   validate.testing.check_brdf("examples/my_brdf.glsl")           # in your own pytest
//
// The header: one `// validate: key=value` per line (see docs/glsl.md). `family` picks the entry
// point; `thresholds` (JSON) become claims `brdfs.technique.my_modified_phong.<metric>`.
// validate: family=brdf
// validate: name=my_modified_phong
// validate: description=modified Phong in GLSL: [rho/pi + k_s (s+2)/(2 pi) max(0, r.v)^s] (n.l) (Lafortune 1994)
// validate: thresholds={"max_rel.modphong_s20": 1e-4, "max_rel.diffuse_r0.8": 1e-4}
// validate: source=Mitsuba's modphong BSDF is this formula in float32 (about 50 operations x 2^-24 = 3e-6 relative); 1e-4 leaves a 30x margin
//
// Entry point of the brdf family: the cosine-weighted BRDF f_r(l, v) max(0, n.l) for unit n, l (to the
// light), v (to the viewer); zero when l or v is below the horizon. The harness declares the material
// uniforms: u_albedo (rho, RGB), u_ks (RGB), u_phong_exponent (s), u_exponent, u_alpha, u_eta, u_k,
// u_sigma, u_minnaert_k, u_distribution. Do not redeclare them, and do not write #version or main().
const float PI = 3.14159265358979324;

vec3 brdf(vec3 n, vec3 l, vec3 v) {
    float nl = dot(n, l);
    if (nl <= 0.0 || dot(n, v) <= 0.0) return vec3(0.0);
    vec3 r = 2.0 * nl * n - l;                        // mirror direction of l about n
    float s = u_phong_exponent;
    float lobe = (s + 2.0) / (2.0 * PI) * pow(max(dot(r, v), 0.0), s);
    return (u_albedo / PI + u_ks * lobe) * nl;
}
