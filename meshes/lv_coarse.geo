// The idealized left ventricle of Land et al. 2015 (problem 2) as a gmsh model:
// a thick-walled prolate spheroid shell truncated by the base plane z = 5 mm.
// Endocardium r_s = 7, r_l = 17 mm; epicardium r_s = 10, r_l = 20 mm (lengths in mm).
//
// All-hexahedral mesh: tetrahedra split into hexahedra (Mesh.SubdivisionAlgorithm = 2).
// Regenerate: gmsh -3 -format msh22 lv_coarse.geo -o lv_coarse.msh
// Physical surfaces (boundary parts): 1 "endocardium", 2 "epicardium", 3 "base";
// physical volume 10 "myocardium".
SetFactory("OpenCASCADE");

rs_endo = 7;  rl_endo = 17;
rs_epi = 10;  rl_epi = 20;
z_base = 5;
// Target element size before subdivision [mm]. The subdivision puts the new boundary nodes on
// the curved surfaces; where the tetrahedra are larger than the radius of curvature (2.9 mm
// at the endocardial apex) that tangles hexahedra: h = 5 gave three cells with a negative
// Jacobian near the endocardial apex, 4.2 ... 4.8 one to five. 3.5 ... 4 give none (checked
// at the corners and the 3 x 3 x 3 Gauss points); 3.8 has the best gmsh distortion of these
// at about the same size as 4.
h = 3.8;

Sphere(1) = {0, 0, 0, 1};
Dilate {{0, 0, 0}, {rs_epi, rs_epi, rl_epi}} { Volume{1}; }
Sphere(2) = {0, 0, 0, 1};
Dilate {{0, 0, 0}, {rs_endo, rs_endo, rl_endo}} { Volume{2}; }
Box(3) = {-2 * rs_epi, -2 * rs_epi, z_base, 4 * rs_epi, 4 * rs_epi, 2 * rl_epi};
BooleanDifference(4) = { Volume{1}; Delete; }{ Volume{2, 3}; Delete; };

// Classify the boundary of the wall: the base is flat in z; of the two curved surfaces the
// endocardium is the narrower (OpenCASCADE bounding boxes of these spline surfaces are loose,
// but clearly ordered).
all() = Boundary{ Volume{4}; };
base() = {}; curved() = {}; width() = {};
For i In {0:#all()-1}
  bb() = BoundingBox Surface{all(i)};
  If (bb(5) - bb(2) < 1e-2)
    base() += all(i);
  Else
    curved() += all(i);
    width() += bb(3) - bb(0);
  EndIf
EndFor
If (#curved() != 2 || #base() != 1)
  Error("expected one flat base and two curved surfaces");
EndIf
If (width(0) < width(1))
  endo() = curved(0); epi() = curved(1);
Else
  endo() = curved(1); epi() = curved(0);
EndIf

Physical Surface("endocardium", 1) = endo();
Physical Surface("epicardium", 2) = epi();
Physical Surface("base", 3) = base();
Physical Volume("myocardium", 10) = {4};

Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
Mesh.SubdivisionAlgorithm = 2;
Mesh.ElementOrder = 1;
