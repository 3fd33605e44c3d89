// A polished gold plate and a gold ball on a grey floor under one sun and a sky: the _Fit texture of an
// include written by `brdf export povray ... --name Gold` (Gold.inc on the Library_Path). A template
// for your own scene (README, "Quickstart"):
//   brdf export povray --model mbk --material Au --sigma-s 0.05 --lc 2 --light-dir -0.3,0.7,0.8 --view-dir 0,0.5,-1 --name Gold -o .
//   povray +I$HOME/.local/share/libbrdf/examples/povray/gold_plate.pov +L$HOME/.local/share/libbrdf/povray +Ogold_povray.png +W640 +H400 +A0.1 -D
#version 3.7;
global_settings { assumed_gamma 1.0 ambient_light 0 max_trace_level 6 }

#include "libbrdf.inc"  // Brdf_Sun
#include "Gold.inc"     // Gold_Fit, Gold_Light_Direction, ...

camera { perspective location <0, 3.6, -6.5> right x * image_width / image_height look_at <0, 0.3, 0> angle 40 }
sky_sphere { pigment { gradient y color_map { [0 rgb 0.9] [1 rgb 0.5] } } }  // neutral: the gold colour is the surface's

// The sun the include was exported for (its _Fit texture holds for any light; colour = irradiance).
Brdf_Sun(Gold_Light_Direction, rgb 1)

plane { y, 0 texture { pigment { rgb 0.3 } finish { diffuse 0.8 ambient 0 } } }
// The plate: a disc with rounded rim; the ball on it.
union {
  cylinder { <0, 0, 0>, <0, 0.12, 0>, 1.55 }
  torus { 1.55, 0.06 translate <0, 0.06, 0> }
  texture { Gold_Fit }
}
sphere { <0.3, 0.72, 0.2>, 0.6 texture { Gold_Fit } }
