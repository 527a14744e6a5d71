import numpy as np, tempfile, shoal, sys
from shoal.cases import still_water_2d, still_water_3d
from shoal.options import SPHOptions
from shoal.probes import PressureSensors
for dim, ch in ((2, 1.0), (2, 1.5), (3, 1.0), (3, 1.2)):
    o = SPHOptions(coef_h=ch)
    if dim == 2:
        case = still_water_2d(dp=0.02, depth=0.4, length=0.8, options=o); pts=[[0.4,0,0.0],[0.4,0,0.1]]; H=0.4
    else:
        case = still_water_3d(dp=0.03, depth=0.3, length=0.3, width=0.3, options=o); pts=[[0.15,0.15,0.0],[0.15,0.15,0.1]]; H=0.3
    case = case.model_copy(update={"probes": [PressureSensors(name="bed", points=pts, interval=0.02)], "end_time": 0.6})
    d = tempfile.mkdtemp(); shoal.run_case(case, d, progress=False, plot=False, overwrite=True)
    data = np.loadtxt(d+"/pressure_bed.csv", delimiter=",", skiprows=1)
    ex = 1000*9.81*(H-np.array(pts)[:,2])
    late = data[data[:,0] >= 0.4, 1:].mean(axis=0)
    print(dim, ch, np.round((late-ex)/(1000*9.81*H)*100, 2), flush=True)
