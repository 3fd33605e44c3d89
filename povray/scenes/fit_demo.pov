// File: fit_demo.pov
// Description: A full scene with the _Fit texture of an include from `brdf export povray` named
//   Material (Material.inc on the Library_Path): three objects on a chequered floor under two
//   suns and a sky, with a perspective camera -- what _Exact cannot do (it holds for one sun and a
//   distant camera only). The first sun shines along Material_Light_Direction.
// Render: brdf export povray ... --name Material -o DIR
//         povray +Ipovray/scenes/fit_demo.pov +LDIR +Lpovray +W640 +H360 +A0.1 +FN
#version 3.7;
global_settings { assumed_gamma 1.0 ambient_light 0 max_trace_level 6 }

#include "libbrdf.inc"
#include "Material.inc"

camera { perspective location <0, 2.2, -6> right x * image_width / image_height look_at <0, 0.6, 0> angle 45 }
sky_sphere { pigment { gradient y color_map { [0 rgb <0.6, 0.7, 0.9>] [1 rgb <0.15, 0.25, 0.6>] } } }

Brdf_Sun(Material_Light_Direction, rgb 1)
Brdf_Sun(<1, 0.6, -0.2>, rgb <0.35, 0.4, 0.5>)  // a second, bluish light: the fit handles any number

plane { y, 0
  texture { pigment { checker rgb 0.6 rgb 0.15 scale 0.75 } finish { diffuse 0.8 ambient 0 } }
}
sphere { <-1.9, 0.8, 0>, 0.8 texture { Material_Fit } }
torus { 0.55, 0.25 texture { Material_Fit } rotate <-70, 0, 0> translate <0, 0.85, 0> }
superellipsoid { <0.3, 0.3> texture { Material_Fit } scale 0.7 rotate <0, 30, 0> translate <1.9, 0.7, 0> }
