// Peer benchmark (docs/PEERS.md): glass_of_liquid.lua for POV-Ray 3.7. Right-handed coordinates as
// in caustica (camera `right -x`), linear output (File_Gamma=1 on the command line), no ambient.
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
  location <0.2, 2.4, 5.2>
  look_at <0.2, 1.98, 4.2>
  right -x
  up y
  angle 38
}

light_source {
  <-2.5, 3.0, 1.5> color rgb <32.5, 31.25, 30>
  fade_distance 0.5 fade_power 2
  photons { refraction on reflection on }
}

#declare Diffuse = finish { ambient 0 diffuse 1 specular 0 phong 0 }
box { <-4, -0.1, -3>, <4, 0, 3> pigment { rgb <0.75, 0.72, 0.66> } finish { Diffuse } }
box { <-4, -0.2, -3.05>, <4, 4.2, -2.95> pigment { rgb <0.55, 0.6, 0.68> } finish { Diffuse } }

// Clear dielectrics: all of ks = 1 split by Fresnel between reflection and transmission.
#declare Clear = texture {
  pigment { rgbf <1, 1, 1, 1> }
  finish { ambient 0 diffuse 0 phong 1 phong_size 120 reflection { 0, 1 fresnel on } conserve_energy }
}

union {
  difference {
    cylinder { <0, 0.002, 0>, <0, 1.302, 0>, 0.5 }
    cylinder { <0, 0.08, 0>, <0, 1.52, 0>, 0.46 }
    texture { Clear }
    interior { ior 1.5 }
  }
  // Beer-Lambert as caustica's kd = <0.85, 0.25, 0.2> per unit distance:
  // exp(-(1 - fade_color) d / fade_distance) = kd^d.
  // Unlike glass_of_liquid.lua the liquid does not reach into the glass: it stops 0.001 short
  // of the cavity. POV-Ray attenuates a ray segment by the interior of the surface that ENDS the
  // segment, so a liquid overlapping the glass would end its long segments at glass surfaces
  // and come out colourless. README.md discusses the (small) optical difference of the gap.
  cylinder {
    <0, 0.081, 0>, <0, 0.81, 0>, 0.459
    texture { Clear }
    interior { ior 1.34 fade_power 1001 fade_distance 0.621335 fade_color <0.899021, 0.138647, 0> }
  }
  translate <0.3, 0, 0.2>
  photons { target reflection on refraction on collect off }
}
