// Fragment shader for spherical harmonics lighting with disc source
varying vec3  diffuseColor;

void main(void)
{
    gl_FragColor = vec4(diffuseColor, 1.0);
}
