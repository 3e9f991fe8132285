-- The memory budget caught by pcall, then an endless loop: the script must stop at once.
local ok = pcall(function() local s = string.rep("x", 1e9) end)
local co = coroutine.wrap(function() return pcall(string.rep, "y", 1e9) end)
pcall(co)
local n = 0
while true do n = n + 1 end
