// Peer benchmark (docs/PEERS.md): glass_sphere.lua for POV-Ray 3.7. Right-handed coordinates as in
// caustica (camera `right -x`), linear output (File_Gamma=1 on the command line), no ambient.
// The photon count, gather count and radius come from the command line (see run.sh).
#version 3.7;
#ifndef (Photons) #declare Photons = 200000; #end
#ifndef (Gather) #declare Gather = 100; #end
// Gather radius: 0.15 is caustica's default maximum distance; 0 leaves it to POV-Ray's estimate.
#ifndef (Radius) #declare Radius = 0.15; #end

global_settings {
  assumed_gamma 1.0
  ambient_light rgb 0
  max_trace_level 8
  adc_bailout 0.001
  photons { count Photons gather 20, Gather #if (Radius > 0) radius Radius #end autostop 0 jitter 0.4 }
}

camera {
  perspective
  location <0, 2.6, 5>
  look_at <0.2, 0.4, 0>
  right -x
  up y
  angle 34
}

light_source {
  <-1.6, 3.4, -0.8> color rgb 10
  fade_distance 0.5 fade_power 2
  photons { refraction on reflection on }
}

box {
  <-4, -0.1, -4>, <4, 0, 4>
  pigment { rgb 0.8 }
  finish { ambient 0 diffuse 1 specular 0 phong 0 }
}

sphere {
  <0, 0.75, 0>, 0.5
  pigment { rgbf <1, 1, 1, 1> }
  finish { ambient 0 diffuse 0 phong 1 phong_size 120 reflection { 0, 1 fresnel on } conserve_energy }
  interior { ior 1.5 }
  photons { target reflection on refraction on collect off }
}
