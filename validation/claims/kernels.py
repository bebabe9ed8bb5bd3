"""Claims of the contact-law kernels: generated blocks against references, errata."""

from .core import Claim, Result, bound_verdict, same

HEADING = 'Contact-law kernels'
INTRO = ("Generated force, torque and Jacobian blocks of every law against complex-step differentiation, 50-digit and float64 central differences and a Taylor test on seeded hypothesis cases (`fricstab verify`), and the errata of the papers' printed Jacobians.")


def kernels_quick():
    """Complex step against the generated K, the six (kn, kt, mu, t) laws, 50 seeded cases."""
    from fricstab.laws import LAW_NAMES
    from fricstab.laws.verify import sample_cases, verify_law
    worst, unexplained = {}, 0
    for name in LAW_NAMES:
        r = verify_law(name, sample_cases(50, 20261121), 20261121)
        worst[name] = r["max_rel_err_complex_step"]
        unexplained += r["complex_step_unexplained_cases"] + r["nonfinite"]
    return Result({"worst": worst, "unexplained": unexplained}, seeds=(20261121,))


def lee_hurley_quick():
    """Complex step against lee_hurley and its wall form, 40 seeded cases per law."""
    from fricstab.laws import verify_lee_hurley as lh
    worst, failed = 0.0, 0
    for law in lh.LAWS:
        rep = lh.verify_cases(lh.sample_cases(40, 20261121, law=law), 20261121, law=law)
        failed += lh.failures(rep)
        for reg in rep["regimes"].values():
            worst = max(worst, reg.get("max_rel_err_complex_step") or 0.0)
    return Result({"worst": worst, "failed": failed}, seeds=(20261121,))


CLAIMS = [
    Claim("kernels.complex_step_quick", "kernels",
          "generated K vs complex step, the six (kn, kt, mu, t) laws, 50 seeded cases each",
          "seconds", "python validation/reproduce.py --claim kernels.complex_step_quick",
          kernels_quick,
          show=lambda v: ", ".join(f"{k} {x:.1e}" for k, x in v["worst"].items())
          + f"; {v['unexplained']} cases unexplained",
          tolerance="worst errors within 10x (round-off of another CPU's instruction "
                    "choice); unexplained count exact",
          check=lambda a, b: (same(keys=["unexplained"])(a, b)[0] and all(
              b["worst"][k] <= 10 * max(a["worst"][k], 1e-16) for k in a["worst"]),
              "worst errors within 10x"),
          verdict=lambda v: bound_verdict(max(v["worst"].values()) if v["unexplained"] == 0
                                          else float("inf"), 1e-12,
                                          "worst row-relative error (bound max(1e-12, 64 eps x "
                                          "cancellation))")),
    Claim("kernels.lee_hurley_quick", "kernels",
          "lee_hurley and its wall form vs complex step, 40 seeded cases per regime",
          "seconds", "python validation/reproduce.py --claim kernels.lee_hurley_quick",
          lee_hurley_quick,
          show=lambda v: f"worst {v['worst']:.1e}; {v['failed']} cases above bound",
          tolerance="worst error within 10x; failures exact",
          check=lambda a, b: (b["failed"] == a["failed"] and b["worst"] <= 10 * a["worst"],
                              f"worst {a['worst']:.1e} -> {b['worst']:.1e}"),
          verdict=lambda v: bound_verdict(v["worst"] if v["failed"] == 0 else float("inf"),
                                          1e-12, "worst error")),
]
