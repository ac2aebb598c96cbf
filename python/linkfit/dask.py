"""linkfit on Dask: tasks solved as a dask.bag on any distributed.Client.

::

    from distributed import Client
    import linkfit.dask
    client = Client("tcp://scheduler:8786")        # or Client(LocalCluster(...))
    results = linkfit.dask.solve_bag(tasks, npartitions=64).compute()

Each partition is solved with :func:`linkfit.solve_many` on its worker (every core of the worker
process, the GIL released), so a worker process per machine with several threads, or several
single-threaded worker processes, both use the machine. Results come back in input order, equal to
``linkfit.solve_many(tasks)``'s. The workers need linkfit installed (the README's first command,
``./scripts/setup.sh``, on each machine).
"""

import dask.bag

import linkfit


def _solve_partition(tasks, threads):
    return linkfit.solve_many(list(tasks), threads=threads)


def solve_bag(tasks, npartitions=None, threads=0):
    """The results of many tasks as a dask.bag, solved on a cluster.

    Each partition is solved by :func:`linkfit.solve_many` on its worker. Call ``.compute()`` on
    the bag, with a ``distributed.Client`` active to run on its cluster (without one, Dask's
    local scheduler runs it).

    Args:
        tasks: a list of tasks (dicts or JSON texts), or a dask.bag of them.
        npartitions (int or None): how many partitions a list is split into (default: about
            100 tasks each); ignored for a bag.
        threads (int): :func:`linkfit.solve_many`'s threads per partition (0: every core of
            the worker).

    Returns:
        dask.bag.Bag: the result dicts, in input order, equal to ``linkfit.solve_many(tasks)``.

    Raises:
        linkfit.InputError: on ``compute()``, bad input in a task of a partition.

    Example:
        >>> results = linkfit.dask.solve_bag(tasks, npartitions=4).compute()
    """
    if isinstance(tasks, dask.bag.Bag):
        bag = tasks
    else:
        tasks = list(tasks)
        if npartitions is None:
            npartitions = max(1, (len(tasks) + 99) // 100)
        bag = dask.bag.from_sequence(tasks, npartitions=max(1, min(npartitions, len(tasks) or 1)))
    return bag.map_partitions(_solve_partition, threads)
