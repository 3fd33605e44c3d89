// File: comparison.pov
// Description: Models side by side (columns) for several surfaces (rows), one sphere each, every
//   sphere textured with the _Exact texture of an include from `brdf export povray`, all baked for
//   the same sun and camera directions. tools/render_povray_comparison.py writes the includes and
//   comparison_materials.inc, which declares:
//     Comparison_Exact           array[Rows][Columns] of textures
//     Comparison_View_Direction  towards the camera (all includes share it)
// Declares (optional): Spacing (centre distance, default 2.3; radius 1).
#version 3.7;
global_settings { assumed_gamma 1.0 ambient_light 0 }

#include "libbrdf.inc"
#include "comparison_materials.inc"

#ifndef(Spacing) #declare Spacing = 2.3; #end
#declare Comparison_Rows = dimension_size(Comparison_Exact, 1);
#declare Comparison_Columns = dimension_size(Comparison_Exact, 2);

// Image axes in the world: the camera looks along -V with the world's y (or z) up.
#declare Comparison_V = vnormalize(Comparison_View_Direction);
#if (abs(Comparison_V.y) > 0.999) #declare Comparison_Sky = z; #else #declare Comparison_Sky = y; #end
#declare Comparison_Right = vnormalize(vcross(Comparison_V, Comparison_Sky));
#declare Comparison_Up = vcross(Comparison_Right, Comparison_V);

Brdf_Ortho_Camera(Comparison_V, <0, 0, 0>, Comparison_Columns * Spacing, Comparison_Rows * Spacing)

#declare Row = 0;
#while (Row < Comparison_Rows)
  #declare Column = 0;
  #while (Column < Comparison_Columns)
    sphere {
      (Column - (Comparison_Columns - 1) / 2) * Spacing * Comparison_Right
        + ((Comparison_Rows - 1) / 2 - Row) * Spacing * Comparison_Up, 1
      texture { Comparison_Exact[Row][Column] }
    }
    #declare Column = Column + 1;
  #end
  #declare Row = Row + 1;
#end
