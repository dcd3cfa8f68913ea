"""The HTTP service (``landscape serve``): the library's landscapes, barrier maps and sweeps over HTTP, with a
page that draws them. Edge layer: it may import everything but the command line (:mod:`landscape.cli`).

Use :func:`landscape.service.app.create_app` with a :class:`landscape.service.config.ServiceConfig`.
"""
