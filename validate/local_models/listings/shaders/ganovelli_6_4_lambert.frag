36 shaderProgram.fragment_shader = “
37 precision highp float;          
38              
39 varying vec3 vnormal;         
40 varying vec3 vpos;          
41 varying vec4 vdiffuse;          
42 uniform vec4 uLightDirection;        
43              
44 // positional light: position and color      
45 uniform vec3 uLightColor;        
46              
47 void main()           
48 {            
49  // normalize interpolated normal       
50  vec3 N = normalize(vnormal);       
51              
52  // light vector (positional light)      
53  vec3 L = normalize(-uLightDirection.xyz);     
54              
55  // diffuse component          
56  float NdotL = max(0.0, dot(N, L));      
57  vec3 lambert = (vdiffuse.xyz * uLightColor) * NdotL; 
58              
59  gl_FragColor = vec4(lambert, 1.0);       
60} “ ;
