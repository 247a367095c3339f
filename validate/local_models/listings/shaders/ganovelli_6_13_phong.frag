74 vec3 phongShading(vec3 L, vec3 N, vec3 V, vec3 lightColor){
75  vec3 mat_ambient = vambient.xyz;     
76  vec3 mat_diffuse = vdiffuse.xyz;     
77  vec3 mat_specular= vspecular.xyz;     
78            
79  vec3 ambient = mat_ambient*lightColor;    
80            
81  // diffuse component        
82  float NdotL = max(0.0, dot(N, L));      
83  vec3 diffuse = (mat_diffuse * lightColor) * NdotL;  
84            
85  // specular component        
86  vec3 R = (2.0 * NdotL * N) - L;      
87  float RdotV = max(0.0, dot(R, V));      
88  float spec = pow(RdotV, vshininess.x);    
89  vec3 specular = (mat_specular * lightColor) * spec;  
90  vec3 contribution = ambient +diffuse + specular;  
91  return contribution;        
92}             
