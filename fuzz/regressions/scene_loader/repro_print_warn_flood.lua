-- print and warn flooded with escapes and a C1 control: bounded in all, made visible.
for i = 1, 5000 do
  print("\27]0;title\7 line " .. i)
  warn("\27[31m", "red ", "\194\155", string.rep("w", 100))
end
error(setmetatable({}, {__tostring = function() return "\27[2J" end}))
