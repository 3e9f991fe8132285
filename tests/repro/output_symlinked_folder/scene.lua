local s = gr.sphere('s'); s:set_material(gr.material({0.8,0.2,0.2},{0,0,0},10))
local l = gr.light({5,5,5},{1,1,1},{1,0,0})
gr.render(s, 'pics/holiday.png', 8, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 50, {0.1,0.1,0.1}, {l})
