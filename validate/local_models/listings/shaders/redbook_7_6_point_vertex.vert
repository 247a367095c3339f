// Vertex shader pulling point-light calculations up from the
// fragment shader.
#version 330 core
uniform mat4 MVPMatrix;
uniform mat3 NormalMatrix;
uniform vec3 LightPosition; // consume in the vertex shader now
uniform vec3 EyeDirection;
uniform float ConstantAttenuation;
uniform float Linear Attenuation;
uniform float QuadraticAttenuation;
in vec4 VertexColor;
in vec3 VertexNormal;
in vec4 VertexPosition;
out vec4 Color;
out vec3 Normal;
// out vec4 Position; // no longer need to interpolate this
out vec3 LightDirection; // send the results instead
out vec3 HalfVector;
out float Attenuation;
void main()
   Color = VertexColor;
   Normal = normalize(NormalMatrix * VertexNormal);
    // Compute these in the vertex shader instead of the fragment shader
    LightDirection = LightPosition - vec3 (VertexPosition);
   float lightDistance = length(LightDirection);
    LightDirection = LightDirection / lightDistance;
Attenuation = 1.0 /
               (ConstantAttenuation +
                 LinearAttenuation * lightDistance +
               QuadraticAttenuation * lightDistance * lightDistance);
   HalfVector = normalize(LightDirection + EyeDirection);
   gl Position = MVPMatrix * VertexPosition;
}
