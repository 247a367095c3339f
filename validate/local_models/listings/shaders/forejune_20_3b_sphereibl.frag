// sphereibl.frag: Source code of fragment shader
uniform samplerCube diffuseMap;
uniform samplerCube specularMap;
varying vec3 reflectDir;    //environment reflection direction
varying vec3 N;

void main()
{
    float c_d = 0.8, c_s = 0.7;

    vec4 diffuseColor=c_d*vec4(vec3(textureCube(diffuseMap, N)), 1);
    vec4 specularColor = c_s * vec4(vec3(textureCube(specularMap,
                                                    reflectDir)), 1 );

    vec4 color = mix ( diffuseColor, specularColor, 0.5 );

    gl_FragColor = color;
}
