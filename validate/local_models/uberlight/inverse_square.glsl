// validate: family=uberlight
// validate: name=glsl_uberlight_inverse_square
// validate: description=GLSL transcription of uberlight_inverse_square: Listing 12.6's superellipse x distance shaping, plastic reflection, falloff 1/d^2
// validate: thresholds={"projector.max_rel": 1.0e-5}
// validate: source=as uberlight_inverse_square (float32 rounding + Mitsuba's bilinear lookup of the projector texture, <= 3e-6 + 7e-7, 10^-5 > 2.5x their sum); the transcription adds float32 rounding only (tests/local_models/test_glsl_techniques.py bounds it)
// validate: seed=002 OpenGL Shading Language §12.4, Listings 12.6/12.7
//
// As validate.local_models.uberlight.orange_book.uberlight_inverse_square (common.shade with F = 1/d^2):
//   (x, y, z) = light coordinates; (x', y') = (x, y)/z; w, h, W = w + width_edge, H = h + height_edge,
//   e1 = 2/roundness, e2 = -roundness/2; inner = w h (|h x'|^e1 + |w y'|^e1)^e2, outer = W H (|H x'|^e1 + |W y'|^e1)^e2,
//   A = 1 - smoothstep(inner, outer, 1) (A = 1 on the axis, 0 behind the light, z <= 0);
//   D = smoothstep(near - near_edge, near, z) (1 - smoothstep(far, far + far_edge, z));
//   L = I0 A D / d^2 (rho/pi max(0, n.l) + ks max(0, n.h)^s), h = normalize(l + v).
// smoothstep with equal edges is the step x >= e1, as in the Python (GLSL leaves it undefined).
const float PI = 3.14159265358979324;

float step_smooth(float e0, float e1, float x) {
    float w = e1 - e0;
    if (!(w > 0.0)) return x >= e1 ? 1.0 : 0.0;
    float t = clamp((x - e0) / w, 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

float pow0(float x, float e) {  // x^e for x >= 0, e > 0 (GLSL's pow is undefined at x = 0)
    return x > 0.0 ? pow(x, e) : 0.0;
}

float superellipse(vec3 lc) {
    if (!(lc.z > 0.0)) return 0.0;
    float px = abs(lc.x / lc.z), py = abs(lc.y / lc.z);
    if (px == 0.0 && py == 0.0) return 1.0;
    float w = u_light_width, h = u_light_height;
    float ww = w + u_light_width_edge, hh = h + u_light_height_edge;
    float e1 = 2.0 / u_light_roundness, e2 = -u_light_roundness / 2.0;
    float inner = w * h * pow(pow0(h * px, e1) + pow0(w * py, e1), e2);
    float outer = ww * hh * pow(pow0(hh * px, e1) + pow0(ww * py, e1), e2);
    return 1.0 - step_smooth(inner, outer, 1.0);
}

float distance_shaping(float z) {
    return step_smooth(u_light_near - u_light_near_edge, u_light_near, z)
         * (1.0 - step_smooth(u_light_far, u_light_far + u_light_far_edge, z));
}

vec3 shade(vec3 p, vec3 n, vec3 v, float albedo) {
    vec3 lc = light_coordinates(p);
    vec3 to_light = u_light_position - p;
    float d = length(to_light);
    vec3 l = to_light / max(d, 1e-30);
    vec3 h = l + v;
    h /= max(length(h), 1e-30);
    float ndotl = max(dot(n, l), 0.0), ndoth = max(dot(n, h), 0.0);
    float refl = albedo / PI * ndotl + u_ks * pow0(ndoth, u_specular_exponent);
    float c = u_light_intensity * superellipse(lc) * distance_shaping(lc.z) / (d * d);
    return vec3(c * refl);
}
