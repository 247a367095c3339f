36 precision highp float;           
37               
38 const int uNLights = “ + nLamps + “;        
39 varying vec3 vnormal;           
40 varying vec3 vpos;           
41 varying vec4 vdiffuse ;          
42               
43 // positional light: position and color       
44 uniform vec4 uLightsGeometry[uNLights];       
45 uniform vec4 uLightsColor[uNLights];        
46               
47 void main()             
48 {              
49  // normalize interpolated normal        
50  vec3 N = normalize(vnormal);          
51  vec3 lambert= vec3(0,0,0);         
52  float r,NdotL;            
53  vec3 L;             
54  for (int i = 0; i <uNLights; {        
55  if (abs(uLightsGeometry[i].w-1.0)<0.01) {     
56  r = 0.03*3.14*3.14*length(uLightsGeometry[i].xyz-vpos);    
57 // light vector (positional light)				 
58 L = normalize(uLightsGeometry[i].xyz-vpos);      
59 }              
60  else {            
61 L = -uLightsGeometry[i].xyz;         
62 r = 1.0;             
63}              
64 // diffuse component          
65 NdotL = max(0.0, dot(N, L))/(r*r);       
66 lambert += (vdiffuse.xyz * uLightsColor[i].xyz) * NdotL;    
67 }              
68  gl_FragColor = vec4(lambert ,1.0) ;        
69}";
