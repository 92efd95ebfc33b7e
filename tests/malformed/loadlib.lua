-- package.loadlib
local limen = require "limen"
local s = limen.scene {}
s:light { pos = {2, 4, 3} }
s:camera { pos = {0, 1, 5}, look_at = {0, 0, 0} }
package.loadlib("/lib/x86_64-linux-gnu/libc.so.6", "system")
return s
