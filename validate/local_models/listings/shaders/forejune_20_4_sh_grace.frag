// Fragment shader for SH lighting of Grace Cathedral

varying vec3 diffuseColor;

void main(void)
{
    gl_FragColor = vec4(diffuseColor, 1.0);
}
