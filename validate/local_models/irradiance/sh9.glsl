// validate: family=irradiance
// validate: name=glsl_sh9
// validate: description=GLSL transcription of sh9: order-2 SH irradiance, R&H 2001 eq. 12 quadratic form
// validate: source=Ramamoorthi & Hanrahan, An Efficient Representation for Irradiance Environment Maps, SIGGRAPH 2001, eq. 12
//
// u_sh[k]: radiance coefficients L00, L1m1, L10, L11, L2m2, L2m1, L20, L21, L22 (world x, y, z
// polynomial basis, no Condon-Shortley phase), as validate.local_models.sh.project_environment gives them.
const float C1 = 0.429043;
const float C2 = 0.511664;
const float C3 = 0.743125;
const float C4 = 0.886227;
const float C5 = 0.247708;

vec3 irradiance(vec3 n) {
    float x = n.x, y = n.y, z = n.z;
    return C1 * u_sh[8] * (x * x - y * y) + C3 * u_sh[6] * z * z + (C4 * u_sh[0] - C5 * u_sh[6])
         + 2.0 * C1 * (u_sh[4] * x * y + u_sh[7] * x * z + u_sh[5] * y * z)
         + 2.0 * C2 * (u_sh[3] * x + u_sh[1] * y + u_sh[2] * z);
}
