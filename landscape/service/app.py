"""The HTTP service of ``landscape serve``: landscapes, barrier maps and sweeps of the library over HTTP, and the
page at ``/`` that draws them.

FastAPI on uvicorn, because FastAPI gives the OpenAPI description and its browsable form at ``/docs`` for free,
validates query parameters and bodies with pydantic (a string where a number belongs is refused before our code
runs), and comes with Starlette's ``TestClient``, so every endpoint is tested in-process without a socket. Every
answer is computed by the library (:func:`landscape.computation.compute`, :func:`~landscape.computation.barrier_map`,
:func:`sim.sweep.run_sweep`, :func:`landscape.viz.sections.build_report`); this module only checks, schedules,
caches and serialises.

Errors: bad input (:class:`geometry.errors.UsageError` and its family) answers 4xx with
``{"detail": "one line saying what is wrong and how to fix it"}``; anything else answers 500 with a generic
message and is logged with its traceback on the server, never sent.
"""

from __future__ import annotations

import asyncio
import json
import logging
import re
import shutil
import tempfile
from contextlib import asynccontextmanager
from importlib.resources import files as package_files
from pathlib import Path
from typing import Annotated

from fastapi import Body, FastAPI, File, Form, Query, Request, UploadFile
from fastapi.exceptions import RequestValidationError
from fastapi.responses import FileResponse, HTMLResponse, JSONResponse, Response
from starlette.background import BackgroundTask
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.staticfiles import StaticFiles

from geometry.bounds import (
    COM_UNCERTAINTY_MM_BOUNDS,
    JOINT_ANGLE_DEG_BOUNDS,
    MASS_KG_BOUNDS,
    MASS_UNCERTAINTY_G_BOUNDS,
    MC_SEED_BOUNDS,
    ORIENTATION_DEG_BOUNDS,
    mass_slip,
)
from geometry.errors import UsageError
from landscape.grid import DEFAULT_STEP_DEG, STEP_DEG_BOUNDS

from .auth import (
    LINK_COOKIE,
    LINK_COOKIE_PATH,
    LINK_TTL_S,
    bearer_ok,
    link_cookie,
    link_cookie_ok,
    opened_by_link,
)
from .config import ServiceConfig
from .errors import NotFoundError, TimeLimitError, TooLargeError, UploadError, status_of
from .inputs import OUT_OF_RANGE, angle_warnings, ranged
from .jobs import SWEEP_BOUNDS, MapJobs, SweepJobs
from .landscapes import SERVICE_SAMPLES_BOUNDS, Landscapes, ResultCache
from .poses import PoseCache, check_pose_request
from .robots import RobotRegistry

log = logging.getLogger(__name__)

STATIC = Path(str(package_files("landscape.service") / "static"))
INTERNAL = (
    "internal error: this is a bug in selfrighting-landscape, not in your input; the server log has details"
)
_PATH = re.compile(r"(?<![\w.:/])/(?!api/)(?:[\w.+@-]+/){2,}([\w.+@-]*)")
_JSON_BODY_BYTES = 1 << 20
MODEL_HELP = (
    "a shipped model set (GET /api/model-sets: paper, physical, physical-head, physical-offset, physical-posed) that poses the wings, as `landscape compute --model NAME`: a "
    "measured set holds each wing servo at its own plateau for the wing command theta_w (60-90); an idealised "
    "set every wing joint at theta_w [default: every wing joint at theta_w]"
)
SWEEP_EXAMPLE = {"theta_w": "74", "theta_l": "30", "cv": "0,0.1", "trials": 2, "duration": 1.0, "dt": 0.001}

SWEEP_DESCRIPTION = (
    "Queue a sweep (the options of `landscape sweep`, same names and defaults); answers the job with its id and "
    "`warnings` (angles that look like radians). Each number is given as a JSON number or as text; the lists "
    "also as `70,72` or `START:STOP:STEP`. Ranges: "
    + "; ".join(f"`{k}` {'each ' if many else ''}{b.text}" for k, (b, many) in SWEEP_BOUNDS.items())
    + " (`dt` null: the robot's default). `robot`: a robot id; `model`: a shipped model set's name."
)

# The numeric parameters, each read through its stated range (landscape.service.inputs.ranged).
ThetaW = ranged(
    JOINT_ANGLE_DEG_BOUNDS, "theta_w", "wing angle, degrees, {range} and within the wing joints' limits"
)
ThetaL = ranged(
    JOINT_ANGLE_DEG_BOUNDS, "theta_l", "leg angle, degrees, {range} and within the leg joint's limits"
)
PoseThetaW = ranged(
    JOINT_ANGLE_DEG_BOUNDS, "theta_w", "wing angle, degrees, {range} (ignored by a rigid robot)"
)
PoseThetaL = ranged(
    JOINT_ANGLE_DEG_BOUNDS, "theta_l", "leg angle, degrees, {range} (ignored by a rigid robot)"
)
Step = ranged(
    STEP_DEG_BOUNDS, "step", f"grid step, degrees, {{range}}; divides 360 [default: {DEFAULT_STEP_DEG:g}]"
)
Pitch = ranged(ORIENTATION_DEG_BOUNDS, "pitch", "body pitch, degrees, {range}")
Roll = ranged(ORIENTATION_DEG_BOUNDS, "roll", "body roll, degrees, {range}")
ThetaWList = ranged(
    JOINT_ANGLE_DEG_BOUNDS,
    "theta_w",
    "wing angles: list 70,72 or range START:STOP:STEP, degrees, each {range} and within the wing joints' limits",
    many=True,
)
ThetaLList = ranged(
    JOINT_ANGLE_DEG_BOUNDS,
    "theta_l",
    "leg angles: list or range, degrees, each {range} and within the leg joint's limits",
    many=True,
)
MassForm = ranged(
    MASS_KG_BOUNDS,
    "mass",
    "mass of a single mesh, kg, {range} (above 1000 kg a warning asks whether it was meant in grams) "
    "[default: 1, said as a default]",
    kind=float | None,
    where=Form,
)


def _plotly_js() -> Path:
    """plotly.js as bundled by the installed ``plotly`` package (the page works offline)."""
    return Path(str(package_files("plotly") / "package_data" / "plotly.min.js"))


def scrub(text: str, *roots: Path) -> str:
    """A message without server paths: the data directory becomes ``DATA``, other absolute paths their last part."""
    for r in roots:
        for form in {str(r.resolve()), str(r)}:
            text = text.replace(form, "DATA")
    return _PATH.sub(r"\1", text)


class _BodyLimit:
    """Refuse request bodies over a size (uploads: the upload limit; everything else: 1 MiB) while they stream."""

    def __init__(self, app, *, upload_bytes: int):
        self.app = app
        self.upload_bytes = upload_bytes

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http" or scope["method"] in ("GET", "HEAD", "DELETE", "OPTIONS"):
            return await self.app(scope, receive, send)
        limit = self.upload_bytes + (1 << 20) if scope["path"] == "/api/robots" else _JSON_BODY_BYTES
        headers = dict(scope.get("headers") or [])
        length = headers.get(b"content-length")
        if length is not None and length.isdigit() and int(length) > limit:
            resp = JSONResponse(
                {
                    "detail": f"request body of {int(length):,} bytes is over the limit of "
                    f"{limit:,} bytes; send a smaller file"
                },
                status_code=413,
            )
            return await resp(scope, receive, send)
        seen = 0
        over = False
        message = f"request body is over the limit of {limit:,} bytes; send a smaller file"

        async def limited():
            nonlocal seen, over
            msg = await receive()
            if msg["type"] == "http.request":
                seen += len(msg.get("body", b""))
                if seen > limit:
                    over = True
                    raise TooLargeError(message)
            return msg

        async def answer(msg):
            # whatever the app made of the interrupted body (a parser's 400), the answer is 413
            if not over:
                return await send(msg)
            if msg["type"] == "http.response.start":
                body = json.dumps({"detail": message}).encode()
                await send(
                    {
                        "type": "http.response.start",
                        "status": 413,
                        "headers": [
                            (b"content-type", b"application/json"),
                            (b"content-length", str(len(body)).encode()),
                        ],
                    }
                )
                await send({"type": "http.response.body", "body": body})

        return await self.app(scope, limited, answer)


def create_app(config: ServiceConfig) -> FastAPI:
    """The service's ASGI app over ``config.data_dir`` (created if absent)."""
    data = Path(config.data_dir)
    data.mkdir(parents=True, exist_ok=True)
    limits = config.limits
    registry = RobotRegistry(data / "robots", limits=limits)
    landscapes = Landscapes(
        registry,
        ResultCache(data / "cache", max_bytes=limits.memory_cache_bytes),
        limits=limits,
        threads=config.compute_threads,
    )
    maps = MapJobs(registry, limits=limits)
    poses = PoseCache()

    def clean(text: str) -> str:
        return scrub(text, data)

    sweeps = SweepJobs(
        data / "sweeps",
        registry,
        limits=limits,
        workers=config.workers,
        scheduler=config.scheduler,
        scrub=lambda s: s.replace(str(data.resolve()), "DATA"),
    )

    @asynccontextmanager
    async def lifespan(app):
        sweeps.start()
        try:
            yield
        finally:
            await asyncio.to_thread(sweeps.stop)
            maps.close()
            landscapes.close()

    app = FastAPI(
        title="selfrighting-landscape",
        version=_package_version(),
        lifespan=lifespan,
        description="Potential-energy landscapes, self-righting barriers and self-righting sweeps.",
    )
    app.state.registry, app.state.landscapes, app.state.maps, app.state.sweeps = (
        registry,
        landscapes,
        maps,
        sweeps,
    )

    # ------------------------------------------------------------------ errors
    @app.exception_handler(UsageError)
    async def _usage(request: Request, exc: UsageError):
        text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        return JSONResponse({"detail": clean(text)}, status_code=status_of(exc))

    @app.exception_handler(TimeLimitError)
    async def _late(request: Request, exc: TimeLimitError):
        return JSONResponse({"detail": str(exc)}, status_code=503, headers={"Retry-After": "5"})

    @app.exception_handler(RequestValidationError)
    async def _invalid(request: Request, exc: RequestValidationError):
        errs = exc.errors()
        e = errs[0] if errs else {"loc": (), "msg": "invalid request"}
        if e.get("type") == OUT_OF_RANGE:  # the command line's words, naming the parameter
            return JSONResponse({"detail": clean(e["msg"])}, status_code=422)
        where = ".".join(str(x) for x in e.get("loc", ()) if x not in ("query", "body", "path"))
        got = f" (got {e['input']!r})" if "input" in e and not isinstance(e["input"], dict | list) else ""
        return JSONResponse(
            {"detail": clean(f"{where}: {e['msg']}{got}" if where else f"{e['msg']}{got}")}, status_code=422
        )

    @app.exception_handler(Exception)
    async def _bug(request: Request, exc: Exception):
        log.error("unexpected error on %s %s", request.method, request.url.path, exc_info=exc)
        return JSONResponse({"detail": INTERNAL}, status_code=500)

    # ------------------------------------------------------------------ middleware
    token = config.token.encode() if config.token else None
    if token is not None:

        @app.middleware("http")
        async def _auth(request: Request, call_next):
            if request.url.path.startswith("/api/") and not (
                bearer_ok(request.headers.get("authorization", ""), token)
                or (
                    opened_by_link(request.method, request.url.path)
                    and link_cookie_ok(request.cookies.get(LINK_COOKIE, ""), token)
                )
            ):
                return JSONResponse(
                    {
                        "detail": "missing or wrong token: send 'Authorization: Bearer TOKEN' "
                        "(the --token or LANDSCAPE_TOKEN the server was started with)"
                    },
                    status_code=401,
                    headers={"WWW-Authenticate": "Bearer"},
                )
            return await call_next(request)

    app.add_middleware(_BodyLimit, upload_bytes=limits.max_upload_bytes)
    if config.allowed_hosts:
        app.add_middleware(TrustedHostMiddleware, allowed_hosts=list(config.allowed_hosts))

    # ------------------------------------------------------------------ page
    @app.get("/", include_in_schema=False)
    async def page():
        return FileResponse(STATIC / "index.html", media_type="text/html")

    @app.get("/static/plotly.min.js", include_in_schema=False)
    async def plotly_js():
        return FileResponse(
            _plotly_js(), media_type="text/javascript", headers={"Cache-Control": "public, max-age=86400"}
        )

    app.mount("/static", StaticFiles(directory=STATIC), name="static")

    @app.post("/api/link-access")
    async def link_access():
        """With a token: a cookie that lets links the page opens in a new tab (a sweep's report and the files it
        links) load without the Authorization header; GET of those paths only, for an hour. No token: no cookie."""
        if token is None:
            return {"cookie": None, "paths": None, "expires_s": None}
        resp = JSONResponse(
            {"cookie": LINK_COOKIE, "paths": "GET /api/sweeps/{id}/report[/{file}]", "expires_s": LINK_TTL_S}
        )
        resp.set_cookie(
            LINK_COOKIE,
            link_cookie(token),
            max_age=LINK_TTL_S,
            path=LINK_COOKIE_PATH,
            httponly=True,
            samesite="strict",
        )
        return resp

    @app.get("/api/health")
    async def health():
        """Liveness, version and cache counters."""
        return {"status": "ok", "version": _package_version(), "cache": dict(landscapes.cache.hits)}

    # ------------------------------------------------------------------ robots
    @app.get("/api/robots")
    async def robots():
        """Every robot: the built-in one (id ``builtin``) and the uploads (id: description hash)."""
        return await asyncio.to_thread(registry.list)

    @app.get("/api/robots/{robot_id}")
    async def robot(robot_id: str):
        """One robot: name, description hash, kind, joint limits of theta_w and theta_l, mass, vertices."""
        return (await asyncio.to_thread(registry.get, robot_id)).info

    @app.post("/api/robots")
    async def upload(
        file: Annotated[UploadFile, File(description="a .zip of a URDF and its meshes, or one mesh file")],
        units: Annotated[str, Form(description="units of a single mesh: mm, cm or m")] = "m",
        mass: MassForm = None,
        com: Annotated[str | None, Form(description="CoM of a single mesh X,Y,Z in its units")] = None,
    ):
        """Store a robot; answers its description (201 new, 200 already stored)."""
        if units not in ("mm", "cm", "m"):
            raise UploadError(f"units must be mm, cm or m; got {units!r}")
        c = None
        if com:
            try:
                c = [float(x) for x in com.split(",")]
            except ValueError:
                raise UploadError(f"com must be X,Y,Z in the mesh's units; got {com!r}") from None
            if len(c) != 3 or not all(abs(x) != float("inf") and x == x for x in c):
                raise UploadError(f"com must be three finite numbers X,Y,Z; got {com!r}")
        info, new = await asyncio.to_thread(
            registry.add_upload, file.filename or "", file.file, units=units, mass_kg=mass, com=c
        )
        slip = mass_slip(mass, "mass")
        if slip and slip not in info["warnings"]:
            info = {**info, "warnings": [*info["warnings"], slip]}
        return JSONResponse(info, status_code=201 if new else 200)

    # ------------------------------------------------------------------ model sets
    @app.get("/api/model-sets")
    async def model_sets():
        """The shipped model sets (the names ``model`` takes): name, version, ``model_set_hash``, ``label``,
        description, profile, ``poses_wings`` (each wing joint at its own measured plateau, else every wing joint
        at theta_w), ``wing_command_deg`` (the measured wing commands theta_w must lie within, or null),
        ``com_offset_y_mm``, ``moves_com`` and ``elements`` (``landscape models --json``)."""
        from .model_sets import model_set_list

        return await asyncio.to_thread(model_set_list)

    # ------------------------------------------------------------------ landscapes
    @app.get("/api/landscape")
    async def landscape_(
        robot: str = Query("builtin", description="robot id (GET /api/robots) or 'builtin'"),
        theta_w: ThetaW = 0.0,
        theta_l: ThetaL = 0.0,
        method: str = Query("exact", description="barrier method: exact, grid or sphere"),
        step: Step = DEFAULT_STEP_DEG,
        format: str = Query(
            "json", pattern="^(json|npz|csv)$", description="json (the summary), npz or csv (the energy grid)"
        ),
        grid: bool = Query(False, description="json: include the energy grid in mJ"),
        model: str | None = Query(None, description=MODEL_HELP),
        com_uncertainty_mm: ranged(
            COM_UNCERTAINTY_MM_BOUNDS,
            "com_uncertainty_mm",
            "CoM uncertainty, mm, {range}: each barrier's interval (barrier.interval)",
        ) = None,
        mass_uncertainty_g: ranged(
            MASS_UNCERTAINTY_G_BOUNDS, "mass_uncertainty_g", "mass uncertainty, g"
        ) = None,
        samples: ranged(
            SERVICE_SAMPLES_BOUNDS,
            "samples",
            "Monte-Carlo samples of the CoM uncertainty, {range} (default: none)",
            kind=int,
        ) = None,
        seed: ranged(MC_SEED_BOUNDS, "seed", "seed of the Monte-Carlo directions", kind=int) = 0,
    ):
        """The object of ``landscape compute --json`` plus the barrier ``paths`` (and, with ``grid=1``, the grid);
        with ``model`` also ``model_set`` and ``wing_joints_deg``, as ``landscape compute --model NAME --json``;
        ``warnings`` when an angle looks like radians (the command line's warning lines);
        with ``com_uncertainty_mm`` or ``mass_uncertainty_g`` also ``barrier.interval``, as ``landscape compute
        --com-uncertainty MM --mass-uncertainty G [--samples N --seed S] --json``. Every answer holds each
        barrier's gradients (``barrier.gradient``)."""
        entry = await asyncio.to_thread(registry.get, robot)
        unc = _uncertainty(com_uncertainty_mm, mass_uncertainty_g, samples, seed)
        key = await asyncio.to_thread(
            landscapes.check, entry, theta_w, theta_l, method, step, model=model, uncertainty=unc
        )
        if format == "json":
            a = await landscapes.answer(entry, key)
            return _with_warnings(
                a.body(grid=grid), angle_warnings(entry.robot, theta_w=theta_w, theta_l=theta_l)
            )
        a = landscapes.cache.get(key)
        if a is None or a.computation is None:
            a = await landscapes.answer(entry, key, need_computation=True)
        return await _download(a, format)

    def _uncertainty(com_mm, mass_g, samples, seed):
        """The request's :class:`landscape.uncertainty.Uncertainty`, or None without one."""
        if com_mm is None and mass_g is None:
            if samples is not None:
                raise UsageError("samples draws CoMs com_uncertainty_mm off; give com_uncertainty_mm too")
            return None
        from landscape.uncertainty import Uncertainty

        return Uncertainty(
            com_m=(com_mm or 0.0) * 1e-3, mass_kg=(mass_g or 0.0) * 1e-3, samples=samples, seed=seed
        ).check()

    async def _download(a, fmt: str):
        from landscape.viz import files

        tmp = Path(tempfile.mkdtemp(prefix="landscape-"))
        await asyncio.to_thread(files.write_computation, a.computation, a.summary, tmp)
        name = f"landscape.{fmt}"
        media = "text/csv" if fmt == "csv" else "application/octet-stream"
        return FileResponse(
            tmp / name,
            media_type=media,
            filename=name,
            background=BackgroundTask(shutil.rmtree, tmp, ignore_errors=True),
        )

    @app.get("/api/robot-pose")
    async def robot_pose(
        robot: str = Query("builtin", description="robot id (GET /api/robots) or 'builtin'"),
        theta_w: PoseThetaW = 0.0,
        theta_l: PoseThetaL = 0.0,
        pitch: Pitch = 0.0,
        roll: Roll = 0.0,
        model: str | None = Query(None, description=MODEL_HELP),
    ):
        """The robot's part meshes (convex hulls) posed at (theta_w, theta_l) and turned to (pitch, roll), resting
        on the ground in the world frame, m: ``parts`` of ``vertices_m`` and ``faces``, ``com_m``,
        ``com_height_m``, ``com_body_m``; with ``model`` the robot as that set models it (as in its landscape),
        named by ``model_set``, ``model_set_hash`` and ``wing_joints_deg``; ``warnings`` when an angle looks like
        radians."""
        entry = await asyncio.to_thread(registry.get, robot)
        key = await asyncio.to_thread(check_pose_request, entry, theta_w, theta_l, pitch, roll, model=model)
        body = await asyncio.to_thread(poses.body, entry, key)
        return _with_warnings(body, angle_warnings(entry.robot, theta_w=theta_w, theta_l=theta_l))

    def _with_warnings(body: bytes, warnings: list[str]) -> Response:
        """A JSON answer, with ``warnings`` added when there are any."""
        if warnings:
            body = json.dumps({**json.loads(body), "warnings": warnings}).encode()
        return Response(body, media_type="application/json")

    # ------------------------------------------------------------------ barrier maps
    def _rows_response(rows: list[dict], fmt: str):
        from landscape.viz import files

        if fmt == "json":
            return rows
        tmp = Path(tempfile.mkdtemp(prefix="barrier-map-"))
        files.write_rows_csv(rows, tmp / "barrier_map.csv")
        return FileResponse(
            tmp / "barrier_map.csv",
            media_type="text/csv",
            filename="barrier_map.csv",
            background=BackgroundTask(shutil.rmtree, tmp, ignore_errors=True),
        )

    @app.get("/api/barrier-map")
    async def barrier_map_(
        robot: str = Query("builtin"),
        theta_w: ThetaWList = "70:76:2",
        theta_l: ThetaLList = "20:50:10",
        step: Step = DEFAULT_STEP_DEG,
        method: str = Query("exact"),
        format: str = Query("json", pattern="^(json|csv)$"),
        model: str | None = Query(None, description=MODEL_HELP),
    ):
        """Barrier rows over theta_w x theta_l (``landscape barrier-map [--model NAME]``): at once if small, else 202
        and a job (whose ``model_set`` and ``wing_joints_deg`` name the set and its wing joints per theta_w)."""
        from .model_sets import map_wing_joints_deg

        entry = await asyncio.to_thread(registry.get, robot)
        ws, ls = theta_w, theta_l  # lists, each value inside its range (ThetaWList, ThetaLList)
        est = maps.check(entry, ws, ls, step, method)
        joints = await asyncio.to_thread(map_wing_joints_deg, model, entry.robot, ws)
        job = maps.start(entry, ws, ls, step, method, model=model, wing_joints_deg=joints)
        if est <= limits.sync_map_s:
            try:
                await asyncio.wait_for(
                    asyncio.shield(asyncio.wrap_future(job.future)), 3 * limits.sync_map_s + 5
                )
            except asyncio.TimeoutError:
                pass
            if job.status == "done":
                return _rows_response(job.rows, format)
            if job.status == "failed":
                raise UsageError(job.error)
        return JSONResponse(
            {
                "job": job.public(),
                "status_url": f"/api/barrier-map/jobs/{job.id}",
                "estimate_s": round(est, 1),
            },
            status_code=202,
        )

    @app.get("/api/barrier-map/jobs/{job_id}")
    async def barrier_map_job(job_id: str, format: str = Query("json", pattern="^(json|csv)$")):
        """A barrier-map job: progress, then its rows (``format=csv``: the rows as CSV once done)."""
        job = maps.get(job_id)
        if format == "csv":
            if job.status != "done":
                raise NotFoundError(
                    f"barrier-map job {job_id} is {job.status}; the CSV exists once it is done"
                )
            return _rows_response(job.rows, "csv")
        return job.public()

    @app.delete("/api/barrier-map/jobs/{job_id}")
    async def cancel_barrier_map(job_id: str):
        """Cancel a barrier-map job (it stops after the pose in progress)."""
        job = maps.get(job_id)
        job.cancel.set()
        return job.public()

    # ------------------------------------------------------------------ sweeps
    @app.post("/api/sweeps", status_code=201, description=SWEEP_DESCRIPTION)
    async def create_sweep(body: Annotated[dict, Body(examples=[SWEEP_EXAMPLE])]):
        return await asyncio.to_thread(sweeps.create, body)

    @app.get("/api/sweeps")
    async def list_sweeps():
        """Every sweep job, oldest first."""
        return await asyncio.to_thread(sweeps.list)

    @app.get("/api/sweeps/{job_id}")
    async def sweep_status(job_id: str):
        """A sweep job: status (queued, running, done, cancelled, failed), done/total, rate (trials/s), ETA (s)."""
        return await asyncio.to_thread(sweeps.status, job_id)

    @app.delete("/api/sweeps/{job_id}")
    async def cancel_sweep(job_id: str):
        """Cancel a sweep job (the stored trials stay; trials in flight are dropped)."""
        return await asyncio.to_thread(sweeps.cancel, job_id)

    @app.get("/api/sweeps/{job_id}/report")
    async def sweep_report(job_id: str):
        """The HTML report of the job's trials (``landscape report``), rebuilt when new trials arrived."""
        page_path = await asyncio.to_thread(sweeps.report, job_id)
        html = page_path.read_text()
        base = f'<base href="/api/sweeps/{job_id}/report/">'  # the report links its tables relative to itself
        html = html.replace("<head>", "<head>" + base, 1) if "<head>" in html else base + html
        return HTMLResponse(html)

    @app.get("/api/sweeps/{job_id}/report/{name}")
    async def sweep_report_file(job_id: str, name: str):
        """A table or figure the report links to."""
        sweeps.status(job_id)
        out = (sweeps.root / job_id / "report").resolve()
        p = (out / name).resolve()
        if not p.is_relative_to(out) or not p.is_file() or name.startswith("."):
            raise NotFoundError(f"report of sweep {job_id} has no file {name!r}")
        return FileResponse(p)

    return app


def _package_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("selfrighting-landscape")
    except PackageNotFoundError:  # pragma: no cover - a source tree
        return "unknown"
