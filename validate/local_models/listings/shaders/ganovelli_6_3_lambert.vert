6 precision highp float;				   
7              
8 uniform mat4 uProjectionMatrix;       
9 uniform mat4 uModelViewMatrix;       
10 mat3 uViewSpaceNormalMatrix;        
11 attribute vec3 aPosition;        
12 attribute vec3 aNormal;         
13 attribute vec4 aDiffuse;        
14 varying vec3 vpos;          
15 varying vec3 vnormal;          
16 varying vec4 vdiffuse ;          
17             
18 void main()            
19 {             
20 // vertex normal (in view space)      
21  vnormal = normalize(uViewSpaceNormalMatrix * aNormal); 
22             
23 // color (in view space)        
24 vdiffuse = aDiffuse;         
25             
26 // vertex position (in view space)      
27 vec4 position = vec4(aPosition, 1.0);     
28 vpos = vec3(uModelViewMatrix * position);    
29             
30 // output           
31 gl_Position = uProjectionMatrix *uModelViewMatrix *  
32  position;          
