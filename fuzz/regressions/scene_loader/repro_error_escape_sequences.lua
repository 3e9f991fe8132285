-- An error carrying terminal escapes (clear screen, window title, clipboard write) and 1 MB
-- more: the message must reach the user bounded, with ESC and BEL made visible.
error("\27[2J\27]0;pwned\7\27]52;c;ZWNobyBoaQ==\7\194\155" .. string.rep("E", 1e6))
