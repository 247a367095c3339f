// validate: family=arealight
// validate: name=glsl_inverse_square
// validate: shapes=sphere,disc
// validate: description=GLSL transcription of inverse_square: point light at the centre, I = pi r^2 L, E = I max(cos theta, 0)/d^2
// validate: source=PBRT 4th ed. §12.1 (E = I cos(theta)/r^2), with a sphere's I = pi r^2 L and a disc's pi r^2 L cos(psi)
//
// As validate.local_models.point_light.inverse_square_light: cos(psi) = m.(p - c)/d for a disc (its
// foreshortening toward the receiver), 1 for a sphere.
const float PI = 3.14159265358979324;

vec3 shade(vec3 p, vec3 n, vec3 v) {
    vec3 to_light = u_area_center - p;
    float d = length(to_light);
    vec3 u = to_light / d;
    float cos_psi = (u_area_shape == 1) ? 1.0 : -dot(u, u_area_normal);
    float intensity = PI * u_area_radius * u_area_radius * u_area_radiance * max(cos_psi, 0.0);
    return vec3(intensity * max(clamp(dot(n, u), -1.0, 1.0), 0.0) / (d * d));
}
