// validate: family=light
// validate: name=glsl_point_inverse_square
// validate: lights=point
// validate: description=GLSL transcription of point_inverse_square: E = I max(0, n.w)/d^2 (Ganovelli eq. 6.37-6.40)
// validate: thresholds={"point.max": 1e-4}
// validate: source=float32 rounding as for point_inverse_square (<= 1e-5 relative), 10x margin (PBRT 4th ed. §12.1: E = I cos(theta)/r^2)
//
// Unshadowed irradiance in W/m^2 (not E/pi); the host multiplies by the scene's shadow-ray test.
vec3 shade(vec3 p, vec3 n, vec3 v) {
    vec3 to_light = u_light_position - p;
    float d = length(to_light);
    float cos_t = dot(n, to_light / d);
    return vec3(u_light_intensity * max(cos_t, 0.0) / (d * d));
}
