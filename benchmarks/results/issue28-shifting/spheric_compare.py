import sys
from shoal.validation.wall_impact import spheric_impact, first_peak, IMPACT_OPTIONS
from shoal.validation.spheric_test2 import load_reference
dp = float(sys.argv[1])
extra = dict(kv.split("=") for kv in sys.argv[2:]) or {"shifting": "none"}
opts = dict(IMPACT_OPTIONS, **extra)
r = spheric_impact(dp, opts)
ref = load_reference()
print("dp", dp, extra, r["particles"], "particles", round(r["seconds"]), "s", flush=True)
for k in r["sensor"]:
    m = first_peak(r["t"], r["sensor"][k], ref["t"], ref["pressure"][k])
    s = m["smoothed"]
    print(f"{k}: dt {s['dt']:+.3f} s  rel {s['rel']*100:+.1f} %  min_after {m['min_after']:.2f} rho g H0  ringing {m['ringing']:.2f}")
