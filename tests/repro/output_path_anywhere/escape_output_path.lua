-- Run WITHOUT -o: the script chooses the output path; absolute and '..' paths are accepted and existing
-- .png files anywhere writable are replaced. (VICTIM: an absolute path outside the current folder.)
local s = gr.sphere('s')
s:set_material(gr.material({0.1,0.9,0.1},{0,0,0},10))
local l = gr.light({5,5,5},{1,1,1},{1,0,0})
gr.render(s, os.getenv('VICTIM'), 32, 32, {0,0,5}, {0,0,-1}, {0,1,0}, 50, {0.1,0.1,0.1}, {l})
gr.render(s, '../outside/new_file_from_script.png', 32, 32, {0,0,5}, {0,0,-1}, {0,1,0}, 50, {0.1,0.1,0.1}, {l})
