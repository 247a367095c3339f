// sphereibl.vert: Source code of vertex shader
uniform mat4.mvpMatrix;
attribute vec4.vPosition;
uniform vec4.eyePosition;
varying vec3.reflectDir; //environment reflection direction
varying vec3.N; //normal at a point

void main()

{
    N = vPosition.xyz;    //normal of a point on sphere
                        // (= vPosition.xyz - origin.xyz)
    vec3 V = eyePosition.xyz - vPosition.xyz;

    N = normalize(N);    //unit normal direction
    V = normalize(V);    //unit view vector

    //environment reflection direction
    reflectDir = 2.0 * dot ( N, V ) * N - V;

    gl_Position = mvpMatrix * vPosition;
}
}
