// validate: family=uberlight
// validate: name=my_elliptic_spot
// validate: description=an elliptical spot: the superellipse at roundness 1 whatever the roundness uniform says, a linear edge ramp instead of smoothstep, falloff 1/d^2, Lambertian only (no ks lobe)
// validate: source=Rost 2006, OpenGL Shading Language 2nd ed., §12.4 Listing 12.6 (roundness 1: inner = 1/|(x'/w, y'/h)|)
//
// A plug-in example for `python -m validate run uberlight --quick --plugin examples/my_uberlight.glsl`:
// exact for the projector (roundness 1, hard edges), off for the barn doors (fitted roundness, soft edges).
const float PI = 3.14159265358979324;

vec3 shade(vec3 p, vec3 n, vec3 v, float albedo) {
    vec3 lc = light_coordinates(p);
    if (!(lc.z > 0.0)) return vec3(0.0);
    vec2 q = lc.xy / lc.z;
    float inner = 1.0 / max(length(q / vec2(u_light_width, u_light_height)), 1e-30);
    float outer = 1.0 / max(length(q / vec2(u_light_width + u_light_width_edge,
                                             u_light_height + u_light_height_edge)), 1e-30);
    float a = outer > inner ? clamp((outer - 1.0) / (outer - inner), 0.0, 1.0) : (inner >= 1.0 ? 1.0 : 0.0);
    vec3 to_light = u_light_position - p;
    float d2 = dot(to_light, to_light);
    float ndotl = max(dot(n, to_light) * inversesqrt(d2), 0.0);
    return vec3(u_light_intensity * a / d2 * albedo / PI * ndotl);
}
