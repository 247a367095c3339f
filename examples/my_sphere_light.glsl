// validate: family=specular_arealight
// validate: name=my_sphere_centre_point
// validate: shapes=sphere
// validate: description=the naive baseline: a point light of the sphere's power at its centre, through GGX (no representative point, no normalisation)
// validate: source=Karis 2013, Real Shading in Unreal Engine 4, p. 14 (the point-light starting point of the representative-point method); GGX: Walter et al. 2007 eq. 33-34
//
// A plug-in example for `python -m validate run arealights --plugin examples/my_sphere_light.glsl`.
const float PI = 3.14159265358979324;

float smith_g1(float c, float a) {
    c = clamp(c, 1e-12, 1.0);
    float t = sqrt(max(1.0 - c * c, 0.0)) / c;
    return 2.0 / (1.0 + sqrt(1.0 + a * a * t * t));
}

vec3 shade(vec3 p, vec3 n, vec3 v) {
    vec3 to_c = u_area_center - p;
    float dist = length(to_c);
    vec3 l = to_c / dist;
    float cl = dot(n, l), cv = dot(n, v);
    if (!(cl > 0.0 && cv > 0.0)) return vec3(0.0);
    vec3 h = normalize(l + v);
    float ch = clamp(dot(n, h), 0.0, 1.0), a2 = u_alpha * u_alpha;
    float dd = ch * ch * (a2 - 1.0) + 1.0;
    float spec = a2 / (PI * dd * dd) * smith_g1(cl, u_alpha) * smith_g1(cv, u_alpha) / (4.0 * cv);
    vec3 f = u_f0 + (1.0 - u_f0) * pow(1.0 - clamp(dot(v, h), 0.0, 1.0), 5.0);
    return f * spec * u_area_radiance * PI * u_area_radius * u_area_radius / (dist * dist);
}
