# What run.sh and float_race.sh share (sourced by both, after `here` is set): the folders and
# thread count, and each scene's caustic region, shadow mask and photon directions a pass.
root=$(cd "$here/../.." && pwd)
build=${BUILD:-$root/build}
out=${OUT:-$root/out/peers}
threads=${THREADS:-2}

# The caustic region of each scene, in pixels of a 512 x 512 render (scaled for other sizes):
# X0 Y0 X1 Y1, and whether only the pixels that are black without caustics count (the shadow
# of a transparent object, lit by the caustic alone; without ambient light the rest is lit
# directly, identically at every photon count, and would only dilute the error).
declare -A region=([glass_sphere]="150 292 470 420" [ring]="200 125 395 375" [glass_of_liquid]="344 205 512 340")
declare -A shadow_only=([glass_sphere]=1 [ring]=0 [glass_of_liquid]=1)
# Photon directions a progressive pass shoots when PP_PHOTONS is not set: the glass of liquid's
# cup covers ~0.45% of the lamp's sphere (the glass sphere and the ring ~1%), so it gets more.
declare -A scene_pp_photons=([glass_sphere]=3000000 [ring]=3000000 [glass_of_liquid]=20000000)

# scaled "V1 V2 ...": values in 512-pixel units at the render's `size`.
scaled() { local v out_=(); for v in $1; do out_+=($((v * size / 512))); done; echo "${out_[*]}"; }
