import fricstab as fs

# 20 disks on a substrate with Ishima's tangential law (no Coulomb cap; defaults in
# Charan's units: kn = 2000, kt = 2 kn/7, F_y = 0.1); F_x ramped on disk 0, the
# history carried by Newton, every pair event bisected to 1e-8
scene = fs.ChainScene(n=20, law="ishima")
ramp = fs.run_ramp(scene, fx_max=0.02, step=1e-3, tol=1e-8)
birth = next(e for e in ramp.events if e.kind == "birth")
print(f"first pair birth at F_x = {birth.fx:.8f} (bracket {birth.fx_hi - birth.fx_lo:.1e})")
