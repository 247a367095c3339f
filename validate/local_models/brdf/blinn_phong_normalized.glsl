// validate: family=brdf
// validate: name=glsl_blinn_phong_normalized
// validate: description=GLSL transcription of blinn_phong_normalized: [rho/pi + k_s (s+8)/(8 pi) (n.h)^s] (n.l) (RTR3 §7.6)
// validate: source=Akenine-Möller, Haines, Hoffman, Real-Time Rendering 3rd ed., §7.6, eq. 7.49
//
// The cosine-weighted BRDF f_r(l, v) max(0, n.l), zero below either horizon, exactly as the Python
// technique blinn_phong_normalized (validate/local_models/classic_brdfs.py).
const float PI = 3.14159265358979324;

vec3 brdf(vec3 n, vec3 l, vec3 v) {
    float nl = dot(n, l);
    float nv = dot(n, v);
    if (nl <= 0.0 || nv <= 0.0) return vec3(0.0);
    vec3 h = normalize(l + v);
    float nh = clamp(dot(n, h), 0.0, 1.0);
    float lobe = (u_exponent + 8.0) / (8.0 * PI) * pow(nh, u_exponent);
    return max((u_albedo / PI + u_ks * lobe) * nl, vec3(0.0));
}
