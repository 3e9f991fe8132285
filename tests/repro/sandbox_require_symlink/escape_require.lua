io.write("require outmod: ", tostring(select(2, pcall(require, 'outmod'))), "\n")
io.write("require pw (-> /etc/passwd): ", tostring(select(2, pcall(require, 'pw'))), "\n")
