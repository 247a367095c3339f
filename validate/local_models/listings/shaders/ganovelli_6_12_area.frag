303 for(int i = 0; i < uNAreaLights; ++i         
304 {
305 vec4 n = uAreaLightsFrame[i] * vec4(0.0,1.0 ,0.0 ,0.0) ;     
306 for(int iy = 0; iy < 3; ++iy)           
307  for(int ix = 0; ix < 2; ++ix)          
308  {
309 float y = float(iy)* (uAreaLightsSize[i].y / 2.0)      
310 - uAreaLightsSize[i].y / 2.0;         
311 float x = float(ix)* (uAreaLightsSize[i].x / 1.0)      
312 - uAreaLightsSize[i].x / 2.0;         
313 vec4 lightPos = uAreaLightsFrame[i] * vec4(x,0.0,y ,1.0) ;   
314 r = length(lightPos.xyz-vpos);          
315 L = normalize(lightPos.xyz-vpos);        
316 if(dot(L,n.xyz) > 0.0) {         
317  NdotL = max(0.0, dot(N, L))/(0.01*3.14 * 3.14 *r*r);     
318  lambert += (uColor.xyz * uAreaLightsColor[i].xyz) * NdotL/(3.0*2.0);  
319}
320 } 
321} 
