"""Parameter sweeps of the VibroImpact FMU on Dask (the command: vibroimpact.cli.sweep).

spec     the FMU's interface, the --set/--grid options, the grid product and the chains (client side)
probe    one instance initialized at the grid's corners before anything is distributed (client side)
point    one chain of points on one FMU instance, statistics on the fly, Poincare samples (worker side)
worker   the plugin that brings the FMU to a worker, and the task that runs one chain
engine   Dask: local cluster or scheduler, the code and the FMU shipped to the workers, progress, CSV files
         written as the points finish (Output: resume, grid order at the end)
bench    a sweep with and without Dask, timed (vibroimpact bench-sweep)
The figures of a sweep are vibroimpact.plotting's.
"""
