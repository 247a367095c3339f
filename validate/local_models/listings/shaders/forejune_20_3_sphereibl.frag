// sphereibl.frag: Source code of fragment shader
uniform samplerCube.cubeEnvMap;
varying vec4.lightReflection;
varying vec3.envReflectDir; //environment reflection direction

void main() {
    vec4 envColor = vec4(vec3(textureCube(cubeEnvMap, envReflectDir)), 1);

float envPercent = 0.7;
vec4 color = mix ( lightReflection, envColor, envPercent );
gl_FragColor = color;
}


actually means

vec3 N = vPosition.xyz - origin.xyz;

and the origin is at $(0, 0, 0)$. (Also note that a translation transformation changes a point but has no effect on a vector.)

A sample output of this application is shown in Figure 20-7(a) with the following parameters:
