// validate: family=specular_arealight
// validate: name=glsl_representative_point
// validate: shapes=sphere
// validate: description=GLSL transcription of representative_point: Karis 2013's point of the sphere closest to the mirror ray, GGX f_r (n.l) E_perp with the (alpha/alpha')^2 normalisation
// validate: source=Karis 2013, Real Shading in Unreal Engine 4, pp. 14-16, eq. 10-14; GGX D and Smith G1: Walter et al. 2007 eq. 33-34
//
// As validate.local_models.specular_arealight.representative_point.representative_point (normalise=True):
// C = (L.r) r - L, l = normalize(L + C saturate(R/|C|)), F(v.h) D(h) G1(l) G1(v) / (4 n.v) E_perp (alpha/alpha')^2,
// E_perp = L_e pi R^2/|L|^2, alpha' = saturate(alpha + R/(2|L|)); zero unless n.l > 0 and n.v > 0.
const float PI = 3.14159265358979324;

float ggx_d(float ch, float a) {
    float a2 = a * a;
    float d = ch * ch * (a2 - 1.0) + 1.0;
    return ch > 0.0 ? a2 / (PI * d * d) : 0.0;
}

float smith_g1(float c, float a) {
    c = clamp(c, 1e-12, 1.0);
    float t = sqrt(max(1.0 - c * c, 0.0)) / c;
    return 2.0 / (1.0 + sqrt(1.0 + a * a * t * t));
}

vec3 shade(vec3 p, vec3 n, vec3 v) {
    float radius = u_area_radius, a = u_alpha;
    vec3 to_c = u_area_center - p;
    float dist = length(to_c);
    vec3 r = 2.0 * dot(n, v) * n - v;
    vec3 c2r = dot(to_c, r) * r - to_c;
    vec3 l = normalize(to_c + c2r * clamp(radius / max(length(c2r), 1e-30), 0.0, 1.0));
    float cl = dot(n, l), cv = dot(n, v);
    if (!(cl > 0.0 && cv > 0.0)) return vec3(0.0);
    vec3 h = normalize(l + v);
    float ch = clamp(dot(n, h), 0.0, 1.0), vh = clamp(dot(v, h), 0.0, 1.0);
    float spec = ggx_d(ch, a) * smith_g1(cl, a) * smith_g1(cv, a) / (4.0 * max(cv, 1e-12));
    float e_perp = u_area_radiance * PI * radius * radius / (dist * dist);
    float k = a / clamp(a + radius / (2.0 * dist), 0.0, 1.0);
    float fc = pow(1.0 - vh, 5.0);
    return max((u_f0 + (1.0 - u_f0) * fc) * (spec * e_perp * k * k), 0.0);
}
