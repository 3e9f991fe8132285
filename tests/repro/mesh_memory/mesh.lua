local m = gr.material({0.8,0.2,0.2},{0,0,0},10)
local l = gr.light({5,5,5},{1,1,1},{1,0,0})
local s = gr.mesh('m', 'tri.obj') s:set_material(m)
gr.render(s, 'x.png', 16, 16, {0.3,0.3,5}, {0,0,-1}, {0,1,0}, 50, {0.1,0.1,0.1}, {l})
