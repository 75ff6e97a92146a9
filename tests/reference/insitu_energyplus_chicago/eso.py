"""Parse eplusout.eso (timestep variables) into a DataFrame indexed by interval START (2006)."""

import pandas as pd


def read_eso(path, year=2006, step_min=10):
    names, data, times = {}, {}, []
    with open(path) as f:
        for line in f:
            if line.startswith("End of Data Dictionary"):
                break
            p = line.rstrip("\n").split(",")
            if len(p) >= 4 and p[0].isdigit() and int(p[0]) > 6:
                names[p[0]] = f"{p[2]}:{p[3].split(' [')[0].split(' !')[0]}"
        for k in names:
            data[k] = []
        for line in f:
            p = line.rstrip("\n").split(",")
            if p[0] == "2":
                month, day, hour, endmin = int(p[2]), int(p[3]), int(p[5]), float(p[7])
                t = pd.Timestamp(year, month, day) + pd.Timedelta(hours=hour - 1, minutes=endmin)
                times.append(t - pd.Timedelta(minutes=step_min))
            elif p[0] in data:
                data[p[0]].append(float(p[1]))
            elif p[0].startswith("End of Data"):
                break
    return pd.DataFrame(
        {names[k]: v for k, v in data.items() if len(v) == len(times)},
        index=pd.DatetimeIndex(times),
    )
