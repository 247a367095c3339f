// validate: family=shadow
// validate: name=glsl_shadow_hard
// validate: description=GLSL transcription of hard: nearest-texel depth test, glPolygonOffset(2, 4)
// validate: source=OpenGL Programming Guide (Red Book) ch. 7: nearest-texel depth comparison with glPolygonOffset(2, 4)
// validate: memory_bytes_per_texel=4
//
// V' in {0, 1}: lit iff z_r <= D + o at the nearest texel, o = factor DZ + units 2^-24; texels outside
// the map are lit (a border depth of 1). As validate.local_models.shadow_map.visibility_hard.
float visibility(vec3 p, vec3 n, vec4 w) {
    int i = int(floor(w.x));
    int j = int(floor(w.y));
    int R = u_shadow_resolution;
    if (i < 0 || j < 0 || i >= R || j >= R) return 1.0;
    vec2 ds = texelFetch(u_shadow_map, ivec2(i, j), 0).rg;
    float occluder = ds.r + u_offset_factor * ds.g + u_offset_units * u_depth_lsb;
    return w.z <= occluder ? 1.0 : 0.0;
}
