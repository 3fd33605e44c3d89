// File: object_check.pov
// Description: One object under the sun and distant camera of a `brdf export povray` include named
//   Material (Material.inc on the Library_Path), for checks against libbrdf (tests/povray/).
// Declares (INI or command line, e.g. Declare=Shape=1):
//   Shape      0 sphere (default), 1 torus, 2 superellipsoid (rounded box), each tilted
//   Pass       0 Material_Exact (default), 1 normal pass (Brdf_Normal_Texture), 2 Material_Fit under Brdf_Sun,
//              3 a plain metallic finish (Blinn highlight of roughness Plain_Roughness) under Brdf_Sun:
//              the reference of tools/bench/renderer_cost.py
//   Frequency  normal pass frequency (1 coarse, 64 fine)
//   Irradiance the sun's irradiance (default 1)
//   View_Width width and height of the orthographic view (default 2.3: the whole unit sphere)
//   Target_X, Target_Y, Target_Z  the point the camera looks at (default the origin; e.g. the
//              specular point of a polished lobe, zoomed with a small View_Width)
#version 3.7;
global_settings { assumed_gamma 1.0 ambient_light 0 max_trace_level 5 }

#ifndef(Shape) #declare Shape = 0; #end
#ifndef(Pass) #declare Pass = 0; #end
#ifndef(Frequency) #declare Frequency = 1; #end
#ifndef(Irradiance) #declare Irradiance = 1; #end
#ifndef(Plain_Roughness) #declare Plain_Roughness = 0.05; #end
#ifndef(View_Width) #declare View_Width = 2.3; #end
#ifndef(Target_X) #declare Target_X = 0; #end
#ifndef(Target_Y) #declare Target_Y = 0; #end
#ifndef(Target_Z) #declare Target_Z = 0; #end
#declare Material_Irradiance = Irradiance;

#include "libbrdf.inc"
#include "Material.inc"

Brdf_Ortho_Camera(Material_View_Direction, <Target_X, Target_Y, Target_Z>, View_Width, View_Width)

#switch (Pass)
  #case (0) #declare Check_Texture = texture { Material_Exact } #break
  #case (1) #declare Check_Texture = texture { Brdf_Normal_Texture(Frequency) } #break
  #case (2)
    #declare Check_Texture = texture { Material_Fit }
    Brdf_Sun(Material_Light_Direction, rgb Irradiance)
  #break
  #case (3)
    #declare Check_Texture = texture {
      pigment { rgb 0.8 }
      finish { ambient 0 diffuse 0 specular 1 roughness Plain_Roughness metallic 1 }
    }
    Brdf_Sun(Material_Light_Direction, rgb Irradiance)
  #break
#end

#switch (Shape)
  #case (0) sphere { 0, 1 texture { Check_Texture } } #break
  #case (1) torus { 0.72, 0.36 texture { Check_Texture } rotate <-60, 20, 0> } #break
  #case (2) superellipsoid { <0.35, 0.35> texture { Check_Texture } scale 0.72 rotate <30, -35, 10> } #break
#end
