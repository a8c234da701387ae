"""pomlab from Python: ctypes over the shared library libpomlab (docs/python.md).

Every function takes a config: a path, or a Config (a file or a text, plus
overrides given as a dict). Each call loads its own copy of the config and
builds its own model, so nothing mutable is shared between calls and the
module may be used from several threads at once (ctypes releases the GIL
while the library computes). Only the calls that write HDF5 files
(montecarlo, study) take a module lock: Debian's HDF5 is not thread-safe.

Units are SI (m, rad, s, J, V) unless a name says otherwise (``_deg``,
``_mm``), as in the JSON of the ``pomlab`` commands. Failures raise
PomlabError with the library's message (file, line, key and value for a
config error); numerical outcomes (an unreachable pose, a maneuver that did
not settle, a solver failure) are data in the returned dicts.
"""

import ctypes
import math
import numbers
import os
import shutil
import tempfile
import threading
from collections import namedtuple

import numpy as np

__all__ = [
    "PomlabError",
    "Config",
    "load",
    "version",
    "architectures",
    "controllers",
    "ik",
    "jacobian",
    "fk",
    "workspace",
    "simulate",
    "metric_keys",
    "montecarlo",
    "study",
    "StudyResult",
]

# ---- the library ------------------------------------------------------------


def _library_path():
    """POMLAB_LIBRARY if set, else the library of the install this package
    belongs to (_install.py, written by cmake --install), else the system's."""
    env = os.environ.get("POMLAB_LIBRARY")
    if env:
        return env
    try:
        from . import _install  # generated at install time
    except ImportError:
        return "libpomlab.so.0"
    here = os.path.dirname(os.path.abspath(__file__))
    return os.path.normpath(os.path.join(here, _install.LIBRARY_FROM_PACKAGE))


class PomlabError(Exception):
    """A failing pomlab call: .status is the symbolic name ("POM_ERR_CONFIG"),
    .code the number, .message the library's message."""

    def __init__(self, status, code, message):
        super().__init__("%s: %s" % (status, message))
        self.status = status
        self.code = code
        self.message = message


class _Error(ctypes.Structure):
    _fields_ = [
        ("status", ctypes.c_int),
        ("message", ctypes.c_char * 1024),
        ("src_file", ctypes.c_char_p),
        ("src_line", ctypes.c_int),
    ]


class _Pose(ctypes.Structure):
    _fields_ = [
        ("reachable", ctypes.c_int),
        ("unreachable_limb", ctypes.c_int),
        ("q", ctypes.c_double * 3),
        ("J", ctypes.c_double * 9),
        ("sv", ctypes.c_double * 3),
        ("kappa", ctypes.c_double),
        ("dexterity", ctypes.c_double),
        ("limit", ctypes.c_double * 12),
        ("violations", ctypes.c_uint),
        ("singular", ctypes.c_int),
        ("n_constraint", ctypes.c_int),
        ("constraint_sv", ctypes.c_double),
        ("constraint_offset", ctypes.c_double),
        ("transmission", ctypes.c_double * 3),
        ("serial_limbs", ctypes.c_uint),
    ]


class _FkInfo(ctypes.Structure):
    _fields_ = [
        ("iterations", ctypes.c_int),
        ("continuation_steps", ctypes.c_int),
        ("residual", ctypes.c_double),
    ]


class _WsResult(ctypes.Structure):
    _fields_ = [
        ("half_width", ctypes.c_double),
        ("capped", ctypes.c_int),
        ("budget_reached", ctypes.c_int),
        ("min_dexterity", ctypes.c_double),
        ("fail_euler", ctypes.c_double * 3),
        ("fail_status", ctypes.c_int),
        ("fail_violations", ctypes.c_uint),
        ("fail_dexterity", ctypes.c_double),
        ("poses", ctypes.c_long),
    ]


class _StudyOpts(ctypes.Structure):
    _fields_ = [
        ("montecarlo", ctypes.c_int),
        ("threads", ctypes.c_int),
        ("resume", ctypes.c_int),
        ("output", ctypes.c_char_p),
        ("tabular", ctypes.c_char_p),
        ("summary", ctypes.c_int),
        ("plots", ctypes.c_int),
        ("cancel", ctypes.POINTER(ctypes.c_int)),
    ]


_P = ctypes.c_void_p
_DEG = math.pi / 180.0  # radians per degree: the library's POM_DEG, the same double
_D3 = ctypes.c_double * 3
_D9 = ctypes.c_double * 9
_E = ctypes.POINTER(_Error)
_S = ctypes.c_char_p
_I = ctypes.c_int


def _declare(lib):
    """Argument and result types of every function used."""
    sig = {
        "pom_api_version": (_S, []),
        "pom_api_git_commit": (_S, []),
        "pom_api_quiet_handlers": (None, []),
        "pom_api_struct_size": (ctypes.c_size_t, [_S]),
        "pom_status_name": (_S, [_I]),
        "pom_cfg_load": (_I, [ctypes.POINTER(_P), _S, _E]),
        "pom_cfg_load_string": (_I, [ctypes.POINTER(_P), _S, _S, _E]),
        "pom_cfg_set_number": (_I, [_P, _S, _S, _S, _E]),
        "pom_cfg_set_string": (_I, [_P, _S, _S, _S, _E]),
        "pom_cfg_destroy": (None, [_P]),
        "pom_cfg_check_overrides": (_I, [_P, _P, _P, _E]),
        "pom_api_arch_type_info": (_I, [_I, ctypes.POINTER(_S), ctypes.POINTER(_S), ctypes.POINTER(_S)]),
        "pom_api_ctrl_type_info": (_I, [_I, ctypes.POINTER(_S), ctypes.POINTER(_S), ctypes.POINTER(_S)]),
        "pom_api_arch_create": (_I, [ctypes.POINTER(_P), _P, _E]),
        "pom_api_arch_destroy": (None, [_P]),
        "pom_api_arch_actuator_unit": (_S, [_P, ctypes.POINTER(ctypes.c_double)]),
        "pom_api_arch_limit_key": (_S, [_P, _I, ctypes.POINTER(ctypes.c_double)]),
        "pom_kin_arch_name": (_S, [_P]),
        "pom_kin_limit_name": (_S, [_P, _I, _S, ctypes.c_size_t]),
        "pom_euler_zyx_to_matrix": (None, [_D9, _D3]),
        "pom_euler_zyx_from_matrix": (_I, [_D3, _D9]),
        "pom_quat_from_matrix": (None, [ctypes.c_double * 4, _D9]),
        "pom_kin_pose_evaluate": (_I, [_P, _D9, ctypes.POINTER(_Pose), _E]),
        "pom_kin_forward": (_I, [_P, _D3, _P, _P, _D9, ctypes.POINTER(_FkInfo), _E]),
        "pom_api_workspace": (_I, [_P, _P, ctypes.POINTER(_WsResult), _D3, _E]),
        "pom_api_sim_create": (_I, [ctypes.POINTER(_P), _P, _I, _E]),
        "pom_api_sim_destroy": (None, [_P]),
        "pom_api_sim_run": (_I, [_P, _D3, _E]),
        "pom_api_sim_name": (_S, [_P]),
        "pom_api_sim_half_stroke": (ctypes.c_double, [_P]),
        "pom_api_sim_status": (_I, [_P, ctypes.POINTER(_S)]),
        "pom_api_metric_count": (_I, []),
        "pom_api_metric_key": (_S, [_I, _S, ctypes.c_size_t]),
        "pom_api_metric_width": (_I, [_I]),
        "pom_api_metric_is_integer": (_I, [_I]),
        "pom_api_sim_metric": (_I, [_P, _I, _D3]),
        "pom_api_sim_samples": (_I, [_P]),
        "pom_api_sim_trace": (ctypes.POINTER(ctypes.c_double), [_P, _S, ctypes.POINTER(_I)]),
        "pom_api_study_defaults": (None, [ctypes.POINTER(_StudyOpts)]),
        "pom_api_check_threads": (_I, [ctypes.c_long, _S, _E]),
        "pom_api_study_run": (
            _I,
            [_P, ctypes.POINTER(_StudyOpts), ctypes.POINTER(ctypes.c_long), ctypes.POINTER(ctypes.c_long), _E],
        ),
        "pom_api_study_run_json": (
            _I,
            [
                _P,
                ctypes.POINTER(_StudyOpts),
                ctypes.POINTER(ctypes.c_long),
                ctypes.POINTER(ctypes.c_long),
                ctypes.POINTER(ctypes.c_void_p),
                _E,
            ],
        ),
        "pom_api_free": (None, [ctypes.c_void_p]),
        "pom_api_gradient_json": (
            _I,
            [_P, ctypes.POINTER(ctypes.c_char_p), _I, ctypes.c_long, ctypes.POINTER(ctypes.c_void_p), _E],
        ),
    }
    for name, (res, args) in sig.items():
        f = getattr(lib, name)
        f.restype = res
        f.argtypes = args
    for name, mirror in (
        ("pom_error", _Error),
        ("pom_kin_pose", _Pose),
        ("pom_kin_fk_info", _FkInfo),
        ("pom_kin_ws_result", _WsResult),
        ("pom_api_study_opts", _StudyOpts),
    ):
        size = lib.pom_api_struct_size(name.encode())
        if size != ctypes.sizeof(mirror):
            raise ImportError(
                "pomlab: %s is %d bytes in the library but %d in this module: "
                "the module and libpomlab are from different versions" % (name, size, ctypes.sizeof(mirror))
            )


_lib = ctypes.CDLL(_library_path())
_declare(_lib)
_lib.pom_api_quiet_handlers()
_METRICS = [
    (
        _lib.pom_api_metric_key(j, ctypes.create_string_buffer(96), 96).decode(),
        _lib.pom_api_metric_width(j),
        bool(_lib.pom_api_metric_is_integer(j)),
    )
    for j in range(_lib.pom_api_metric_count())
]
# HDF5 (Debian's serial build) is not thread-safe: one study at a time.
_hdf5_lock = threading.Lock()


def _check(status, err):
    if status != 0:
        name = _lib.pom_status_name(status).decode()
        raise PomlabError(name, status, err.message.decode(errors="replace"))


def _text(b):
    return b.decode(errors="replace") if b is not None else None


def _refuse(message):
    raise PomlabError("POM_ERR_ARG", -4, message)


def _no_nul(what, s):
    """s as given to the library: a C string ends at its first NUL byte,
    which would cut a key, a value, a path or a config text short
    silently, so a NUL is refused here, before ctypes sees the string."""
    if isinstance(s, bytes):
        s = s.decode(errors="replace")
    k = s.find("\x00")
    if k >= 0:
        _refuse(
            "%s %r: a NUL byte at offset %d (refused: the library would read only what comes before it)"
            % (what, s if len(s) <= 80 else s[:77] + "...", k)
        )
    return s


def _number_text(key, value):
    """An override's value as the program's command line would write it: an
    integer (Python's or numpy's) as its digits, a real (float, numpy's) by
    repr; booleans and anything else refused, naming the key."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        _refuse("override %s = %r: a number or a string is expected (a %s)" % (key, value, type(value).__name__))
    if isinstance(value, numbers.Integral):
        return str(int(value))
    return repr(float(value))


def _threads(threads):
    """threads as the program's --threads checks it (pom_api_check_threads):
    an integer in [1, POM_API_THREADS_MAX], or 0 for study.threads."""
    if isinstance(threads, (bool, np.bool_)) or not isinstance(threads, numbers.Integral):
        _refuse(
            "threads = %r: expected an integer in [1, 1024] worker threads (0 = study.threads, else every core)"
            % (threads,)
        )
    t = int(threads)
    if abs(t) > 2**62:  # beyond a C long: the library's message, with Python's digits
        _refuse("threads = %d: expected an integer in [1, 1024] worker threads (0 = study.threads)" % t)
    err = _Error()
    _check(_lib.pom_api_check_threads(t, b"threads", err), err)
    return t


# ---- configs -------------------------------------------------------------------


def _flatten(overrides, prefix=""):
    """{"controller": {"kp": 1}} and {"controller.kp": 1} alike, as pairs."""
    for key, value in overrides.items():
        if not isinstance(key, str):
            _refuse("override key %r: a string is expected (\"controller.kp\" or nested dicts)" % (key,))
        full = prefix + key
        if isinstance(value, dict):
            yield from _flatten(value, full + ".")
        else:
            yield full, value


class Config:
    """A config file (path) or text, and overrides set on it as if the file
    said so: a dict of dotted keys ("controller.kp") or nested groups to
    numbers or strings. Plain data: every call loads its own copy."""

    def __init__(self, path=None, *, text=None, overrides=None, name="<text>"):
        if (path is None) == (text is None):
            raise ValueError("pomlab.Config: give a path or a text, not both")
        self.path = os.fspath(path) if path is not None else None
        self.text = text
        self.name = name
        self.overrides = dict(_flatten(overrides or {}))

    def with_overrides(self, overrides):
        """A new Config with more overrides (these win)."""
        c = Config(self.path, text=self.text, name=self.name) if self.path else Config(text=self.text, name=self.name)
        c.overrides = dict(self.overrides)
        c.overrides.update(_flatten(overrides or {}))
        return c

    def __repr__(self):
        src = self.path if self.path is not None else self.name
        return "pomlab.Config(%r, overrides=%r)" % (src, self.overrides)


def load(path=None, *, text=None, overrides=None, name="<text>"):
    """A Config, loaded once now so that a missing file, a syntax error or a
    bad override raises here (PomlabError)."""
    cfg = Config(path, text=text, overrides=overrides, name=name)
    _Loaded(cfg).close()
    return cfg


def _as_config(cfg, overrides):
    if isinstance(cfg, Config):
        return cfg.with_overrides(overrides) if overrides else cfg
    return Config(cfg, overrides=overrides)


class _Loaded:
    """One call's own pom_cfg."""

    def __init__(self, cfg):
        self.ptr = _P()
        err = _Error()
        # every string checked before the library sees any of them
        if cfg.path is not None:
            _no_nul("config path", cfg.path)
        else:
            _no_nul("config text", cfg.text)
            _no_nul("config name", cfg.name)
        values = []
        for key, value in cfg.overrides.items():
            _no_nul("override key", key)
            if isinstance(value, str):
                values.append((key, _no_nul("override %s =" % key, value), True))
            else:
                values.append((key, _number_text(key, value), False))
        if cfg.path is not None:
            st = _lib.pom_cfg_load(ctypes.byref(self.ptr), cfg.path.encode(), err)
        else:
            st = _lib.pom_cfg_load_string(ctypes.byref(self.ptr), cfg.text.encode(), cfg.name.encode(), err)
        _check(st, err)
        try:
            for key, text, is_string in values:
                origin = ("override %s" % key).encode()
                setter = _lib.pom_cfg_set_string if is_string else _lib.pom_cfg_set_number
                st = setter(self.ptr, key.encode(), text.encode(), origin, err)
                _check(st, err)
        except BaseException:
            self.close()
            raise

    def close(self):
        if self.ptr:
            _lib.pom_cfg_destroy(self.ptr)
            self.ptr = _P()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _overrides_read(loaded):
    """ik and fk read the architecture alone: an override of any other group
    (pom_api_arch_create leaves the workspace's to pom_api_workspace) is
    refused, as an unknown key of the command."""
    err = _Error()
    _check(_lib.pom_cfg_check_overrides(loaded.ptr, None, None, err), err)


class _Arch:
    """One call's own architecture (pom_api_arch_create)."""

    def __init__(self, cfg_ptr):
        self.ptr = _P()
        err = _Error()
        _check(_lib.pom_api_arch_create(ctypes.byref(self.ptr), cfg_ptr, err), err)

    def close(self):
        if self.ptr:
            _lib.pom_api_arch_destroy(self.ptr)
            self.ptr = _P()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


# ---- registries and version -------------------------------------------------------------


def version():
    """{"version": "0.1.0", "git_commit": "..."} of the library."""
    return {"version": _lib.pom_api_version().decode(), "git_commit": _lib.pom_api_git_commit().decode()}


def _registry(info):
    out, k = [], 0
    a, b, c = _S(), _S(), _S()
    while info(k, ctypes.byref(a), ctypes.byref(b), ctypes.byref(c)) == 0:
        out.append((_text(a.value), _text(b.value), _text(c.value)))
        k += 1
    return out


def architectures():
    """The registered architectures: dicts of name (the config value),
    label and actuator_kind."""
    return [dict(name=n, label=l, actuator_kind=k) for n, l, k in _registry(_lib.pom_api_arch_type_info)]


def controllers():
    """The registered controller types: dicts of name (controller.type),
    label and description."""
    return [dict(name=n, label=l, description=d) for n, l, d in _registry(_lib.pom_api_ctrl_type_info)]


# ---- kinematics ---------------------------------------------------------------------------


def _vec(a, n, scale=1.0):
    return np.array([a[k] * scale for k in range(n)], dtype=float)


def _pose_dict(arch, pose, st, err):
    """The pose as `pomlab ik --json` gives it (SI, limits in their JSON units)."""
    f = ctypes.c_double()
    unit = _lib.pom_api_arch_actuator_unit(arch, ctypes.byref(f)).decode()
    d = {
        "actuator_unit": unit,
        "reachable": bool(pose.reachable),
        "unreachable_limb": pose.unreachable_limb + 1 if pose.unreachable_limb >= 0 else None,
    }
    keys = []
    for kind in range(1, 4):
        k = _lib.pom_api_arch_limit_key(arch, kind, ctypes.byref(f))
        if k is not None:
            keys.append((kind, k.decode(), f.value))
    if not pose.reachable:
        d.update(q=None, jacobian=None, singular_values=None, kappa=None, dexterity=None)
        d.update({k: None for _, k, _ in keys})
        d.update(within_limits=False, violations=[])
        if pose.singular & 1:
            d["singularities"] = ["serial"]
            d["serial_limbs"] = [i + 1 for i in range(3) if pose.serial_limbs >> i & 1]
    else:
        d["q"] = _vec(pose.q, 3)
        d["jacobian"] = _vec(pose.J, 9).reshape(3, 3)
        d["singular_values"] = _vec(pose.sv, 3)
        d["kappa"] = pose.kappa
        d["dexterity"] = pose.dexterity
        d["singularities"] = [n for b, n in ((1, "serial"), (2, "parallel"), (4, "constraint")) if pose.singular & b]
        d["transmission"] = _vec(pose.transmission, 3)
        d["serial_limbs"] = [i + 1 for i in range(3) if pose.serial_limbs >> i & 1]
        if pose.n_constraint:
            d["constraint_sv"] = pose.constraint_sv
            d["constraint_offset_m"] = pose.constraint_offset
        for kind, k, scale in keys:
            d[k] = np.array([pose.limit[3 * kind + i] * scale for i in range(3)])
        d["within_limits"] = pose.violations == 0
        buf = ctypes.create_string_buffer(64)
        d["violations"] = [
            _lib.pom_kin_limit_name(arch, k, buf, 64).decode() for k in range(12) if pose.violations & (1 << k)
        ]
    d["message"] = "" if st == 0 else err.message.decode(errors="replace")
    return d


def _rotation(euler_zyx, degrees):
    e = [float(v) for v in euler_zyx]
    if len(e) != 3 or not all(math.isfinite(v) for v in e):
        raise ValueError("euler_zyx: three finite angles (psi, theta, phi) expected, got %r" % (euler_zyx,))
    if degrees:
        e = [v * _DEG for v in e]
    R = _D9()
    _lib.pom_euler_zyx_to_matrix(R, _D3(*e))
    return R


def ik(cfg, euler_zyx, *, degrees=False, overrides=None):
    """Inverse kinematics of the platform orientation R = Rz(psi) Ry(theta)
    Rx(phi) (radians, or degrees with degrees=True): a dict with the keys of
    `pomlab ik --json` (q in m or rad, jacobian 3x3 with q_dot = J omega,
    singular_values, kappa, dexterity, the limits, within_limits,
    violations, message). An unreachable pose or a violated limit is data
    (reachable, within_limits), not an exception."""
    c = _as_config(cfg, overrides)
    R = _rotation(euler_zyx, degrees)
    with _Loaded(c) as L, _Arch(L.ptr) as A:
        _overrides_read(L)
        pose, err = _Pose(), _Error()
        st = _lib.pom_kin_pose_evaluate(A.ptr, R, ctypes.byref(pose), err)
        if st not in (0, -5, -6):  # ok, unreachable, limit: reported in the dict
            _check(st, err)
        d = {"architecture": _lib.pom_kin_arch_name(A.ptr).decode()}
        d.update(_pose_dict(A.ptr, pose, st, err))
        return d


def jacobian(cfg, euler_zyx, *, degrees=False, overrides=None):
    """The Jacobian J (3x3 numpy array, m/rad or rad/rad; q_dot = J omega,
    omega in the fixed frame) at an orientation. PomlabError when the pose
    cannot be assembled."""
    d = ik(cfg, euler_zyx, degrees=degrees, overrides=overrides)
    if not d["reachable"]:
        raise PomlabError("POM_ERR_UNREACHABLE", -5, d["message"])
    return d["jacobian"]


def fk(cfg, q, *, overrides=None):
    """Forward kinematics of actuator coordinates q (m or rad from
    mid-stroke): a dict with the keys of `pomlab fk --json` (solved,
    rotation 3x3, euler_zyx (rad) and euler_zyx_deg, euler_singular,
    quaternion_wxyz, iterations, continuation_steps, residual, and the pose
    at that rotation). Without convergence: solved False and message."""
    c = _as_config(cfg, overrides)
    qv = [float(v) for v in q]
    if len(qv) != 3:
        raise ValueError("q: three actuator coordinates expected")
    with _Loaded(c) as L, _Arch(L.ptr) as A:
        _overrides_read(L)
        R, info, err = _D9(), _FkInfo(), _Error()
        st = _lib.pom_kin_forward(A.ptr, _D3(*qv), None, None, R, ctypes.byref(info), err)
        d = {"architecture": _lib.pom_kin_arch_name(A.ptr).decode(), "q_target": np.array(qv)}
        if st != 0:
            if st != -8:  # not converging is an outcome; anything else an error
                _check(st, err)
            d.update(solved=False, iterations=info.iterations, message=err.message.decode(errors="replace"))
            return d
        e, quat = _D3(), (ctypes.c_double * 4)()
        est = _lib.pom_euler_zyx_from_matrix(e, R)
        _lib.pom_quat_from_matrix(quat, R)
        d["solved"] = True
        d["rotation"] = _vec(R, 9).reshape(3, 3)
        d["euler_zyx"] = _vec(e, 3)
        d["euler_zyx_deg"] = _vec(e, 3, 1.0 / _DEG)
        d["euler_singular"] = est != 0
        d["quaternion_wxyz"] = _vec(quat, 4)
        d.update(iterations=info.iterations, continuation_steps=info.continuation_steps, residual=info.residual)
        pose, perr = _Pose(), _Error()
        pst = _lib.pom_kin_pose_evaluate(A.ptr, R, ctypes.byref(pose), perr)
        d.update(_pose_dict(A.ptr, pose, pst, perr))
        return d


def workspace(cfg, *, overrides=None):
    """The regular dexterous workspace (the `workspace` group of the config
    over its defaults) and the global conditioning index, as `pomlab
    workspace --json`: half_width (rad) and half_width_deg, capped,
    budget_reached, min_dexterity, first_failure, gci, gci_half_width_deg,
    gci_usable_fraction, poses_evaluated."""
    c = _as_config(cfg, overrides)
    with _Loaded(c) as L, _Arch(L.ptr) as A:
        res, out, err = _WsResult(), _D3(), _Error()
        _check(_lib.pom_api_workspace(A.ptr, L.ptr, ctypes.byref(res), out, err), err)
        first = None
        if not (res.capped or res.budget_reached):
            first = {
                "euler_zyx_deg": _vec(res.fail_euler, 3, 1.0 / _DEG),
                "status": _lib.pom_status_name(res.fail_status).decode(),
            }
        return {
            "architecture": _lib.pom_kin_arch_name(A.ptr).decode(),
            "half_width": res.half_width,
            "half_width_deg": res.half_width / _DEG,
            "capped": bool(res.capped),
            "budget_reached": bool(res.budget_reached),
            "min_dexterity": res.min_dexterity,
            "first_failure": first,
            "gci": out[0],
            "gci_half_width_deg": out[2] / _DEG,
            "gci_usable_fraction": out[1],
            "poses_evaluated": res.poses,
        }


# ---- one maneuver ---------------------------------------------------------------------


def metric_keys():
    """The metrics simulate returns: (JSON key, width, integer) in schema order."""
    return list(_METRICS)


_TRACE_COLUMNS = ("t", "q", "q_dot", "current", "voltage", "energy", "euler_zyx", "quat", "deflection")


def simulate(cfg, target, *, traces=True, overrides=None):
    """One maneuver from rest at mid-stroke to target (m, or rad for rotary
    actuators, per actuator), as `pomlab simulate --json`: a dict of every
    metric under its JSON key (execution_time_s, energy_total_J, ...; a
    float, an int for counts and flags, a numpy array of 3 per actuator; NaN
    where the JSON says null), plus name, status, reason and half_stroke;
    with traces=True also "traces", a dict of numpy arrays (t [n], q, q_dot,
    current, voltage, energy, euler_zyx [n, 3], quat [n, 4], deflection
    [n]). A numerical failure is reported in status and reason; a config
    error or a target outside the stroke raises PomlabError."""
    c = _as_config(cfg, overrides)
    tv = [float(v) for v in target]
    if len(tv) != 3:
        raise ValueError("target: three actuator setpoints expected")
    with _Loaded(c) as L:
        sim, err = _P(), _Error()
        _check(_lib.pom_api_sim_create(ctypes.byref(sim), L.ptr, 1 if traces else 0, err), err)
    try:
        st = _lib.pom_api_sim_run(sim, _D3(*tv), err)
        if st == -4:  # refused before running: not a maneuver outcome
            _check(st, err)
        reason = _S()
        status = _lib.pom_api_sim_status(sim, ctypes.byref(reason))
        d = {
            "name": _lib.pom_api_sim_name(sim).decode(errors="replace"),
            "status": _lib.pom_status_name(status).decode(),
            "reason": _text(reason.value),
            "half_stroke": _lib.pom_api_sim_half_stroke(sim),
        }
        v = _D3()
        for j, (key, width, integer) in enumerate(_METRICS):
            _lib.pom_api_sim_metric(sim, j, v)
            vals = [v[k] for k in range(width)]
            if integer:
                vals = [int(x) if math.isfinite(x) else x for x in vals]
            if width == 1:
                d[key] = vals[0]
            elif integer and all(isinstance(x, int) for x in vals):
                d[key] = np.array(vals, dtype=np.int64)
            else:
                d[key] = np.array(vals, dtype=float)
        if traces:
            n = _lib.pom_api_sim_samples(sim)
            tr = {}
            for name in _TRACE_COLUMNS:
                w = _I()
                p = _lib.pom_api_sim_trace(sim, name.encode(), ctypes.byref(w))
                a = np.ctypeslib.as_array(p, shape=(n * w.value,)).copy() if n > 0 else np.zeros(0)
                tr[name] = a if w.value == 1 else a.reshape(n, w.value)
            d["traces"] = tr
        return d
    finally:
        _lib.pom_api_sim_destroy(sim)


# ---- Monte-Carlo runs and studies -------------------------------------------------------

StudyResult = namedtuple("StudyResult", ["rows", "candidates", "results", "report", "summary"])
StudyResult.__doc__ = """rows: a pandas DataFrame, one row per candidate x maneuver
(candidate, factors, maneuver, drawn values, actuator_unit, every metric,
status, reason: the tabular file of docs/results.md); candidates: one row per
candidate (counts and statistics; with study.capability, a column
capability_<figure> per capability figure asked, in SI, NaN where not
computed, and capability_met with study.capability_require); results: the
path of the HDF5 results file; report: the report as `pomlab study --json` prints it, parsed (a
dict); summary: the path of summary.md (None when not written)."""

# How often the calling thread looks for Ctrl-C while a run goes (s).
_POLL_S = 0.05


def _run_study(cfg, montecarlo, output, threads, resume, summary, plots):
    import json

    import pandas as pd

    made = None
    if output is None:
        made = tempfile.mkdtemp(prefix="pomlab-")
        output = os.path.join(made, "results.h5")
    output = os.fspath(output)
    stem = output[:-3] if output.endswith(".h5") else output
    tabular = stem + ".csv"
    cancel = ctypes.c_int(0)
    opts = _StudyOpts()
    _lib.pom_api_study_defaults(ctypes.byref(opts))
    opts.montecarlo = 1 if montecarlo else 0
    opts.threads = threads
    opts.resume = 1 if resume else 0
    opts.output = output.encode()
    opts.tabular = tabular.encode()
    opts.summary = 1 if summary else 0
    opts.plots = 1 if plots else 0
    opts.cancel = ctypes.pointer(cancel)
    done, total, err, report = ctypes.c_long(), ctypes.c_long(), _Error(), ctypes.c_void_p()
    outcome = {}

    def work(ptr):
        outcome["status"] = _lib.pom_api_study_run_json(
            ptr, ctypes.byref(opts), ctypes.byref(done), ctypes.byref(total), ctypes.byref(report), err
        )

    try:
        with _Loaded(cfg) as L, _hdf5_lock:
            # the run goes on a worker thread so that this one sees Ctrl-C at
            # once: it sets the cancel flag, the runs stop after the running
            # maneuvers and OUTPUT.partial keeps the finished ones (resume=True)
            worker = threading.Thread(target=work, args=(L.ptr,), name="pomlab-study")
            worker.start()
            try:
                while worker.is_alive():
                    worker.join(_POLL_S)
            except KeyboardInterrupt:
                cancel.value = 1
                while worker.is_alive():
                    try:
                        worker.join(_POLL_S)
                    except KeyboardInterrupt:
                        pass
                raise
        st = outcome["status"]
        if st == -15:  # POM_ERR_INTERRUPTED: only the cancel flag stops a run here
            raise KeyboardInterrupt(err.message.decode(errors="replace"))
        _check(st, err)
        text = ctypes.string_at(report.value).decode() if report.value else "{}"
    except BaseException as exc:
        # nothing worth keeping in a folder this call made (an interrupted
        # run into a given output keeps its .partial for resume=True)
        if made:
            shutil.rmtree(made, ignore_errors=True)
        raise exc
    finally:
        if report.value:
            _lib.pom_api_free(report)
            report.value = None
    rows = pd.read_csv(tabular)
    candidates = pd.read_csv(stem + "_candidates.csv")
    summary_path = None
    if summary:
        # the library's rule (pom_job_summary_dir): results/x.h5 -> results/x/
        base = os.path.basename(output)
        folder = output[: output.rfind(".")] if "." in base[1:] else output + "_summary"
        summary_path = os.path.join(folder, "summary.md")
    return StudyResult(rows, candidates, output, json.loads(text), summary_path)


def montecarlo(
    cfg, *, n=None, seed=None, threads=0, output=None, resume=False, summary=True, plots=True, overrides=None
):
    """N random maneuvers of the one mechanism a config describes (its
    `montecarlo` group; n and seed override montecarlo.maneuvers and
    montecarlo.seed), as `pomlab montecarlo --out output --tabular`: the same
    job, output rules, report and summary. Writes the HDF5 results file
    `output` (default: results.h5 in a new temporary folder, kept), its
    tables beside it (.csv, _candidates.csv) and summary.md with figures in
    the folder of output without .h5 (summary, plots). Ctrl-C stops within a
    second and raises KeyboardInterrupt, the finished maneuvers kept in
    output.partial (resume=True continues). Returns a StudyResult."""
    threads = _threads(threads)
    # n and seed go in as the program's --n and --seed do: values of
    # montecarlo.maneuvers and montecarlo.seed, checked by the config's
    # getters (an integer in range; 1.5, True or "5" refused, naming the key)
    extra = {}
    if n is not None:
        extra["montecarlo.maneuvers"] = n
    if seed is not None:
        extra["montecarlo.seed"] = seed
    extra.update(dict(_flatten(overrides or {})))
    return _run_study(_as_config(cfg, extra), True, output, threads, resume, summary, plots)


def study(cfg, *, n=None, threads=0, output=None, resume=False, summary=True, plots=True, overrides=None):
    """A whole study file (candidates x maneuvers), as `pomlab study --out
    output --tabular`: the same job (synthesis and tuning first when
    candidates ask for them, their files in the folder of output without
    .h5; study.fidelity = "auto"; the runs; the report), the same output
    rules and the same summary.md and figures. n overrides
    montecarlo.maneuvers. Ctrl-C stops within a second and raises
    KeyboardInterrupt, the finished maneuvers kept in output.partial
    (resume=True continues). Returns a StudyResult (rows, candidates,
    results file, report, summary; default output: results.h5 in a new
    temporary folder)."""
    threads = _threads(threads)
    extra = {"montecarlo.maneuvers": n} if n is not None else {}
    extra.update(dict(_flatten(overrides or {})))
    return _run_study(_as_config(cfg, extra), False, output, threads, resume, summary, plots)


def gradient(cfg, params, *, maneuvers=None, sens_margin=None, quantile=None, bandwidth_ms=None,
             sens_error_test=None, overrides=None):
    """Design gradients (docs/optimize.md section 12): the metrics of the
    config's Monte-Carlo maneuvers and their derivatives with respect to
    the numeric config keys `params` (a list, at most 16; an array element
    as "key[i]"), by forward sensitivities through the exact formulation
    (the config must say joints.model = "rigid"). Derivatives are per unit
    of each key as written in the config. Returns the dict `pomlab gradient
    --json` prints: per maneuver "metrics", "gradient" (a list per metric,
    None where undefined) and "undefined" (the reasons), the peak coil
    current's argmax "peak_current_at" (time in s, coil from 1; its
    derivative by the envelope theorem, docs/optimize.md 12.2), then "mean"
    and "mean_gradient", and "quantile": the smooth robust statistic of the
    times over the maneuvers (the kernel-smoothed quantile of
    docs/optimize.md 11.3 and 12.3; "p", "bandwidth_s", "value",
    "gradient", "undefined"); quantile and bandwidth_ms set
    gradient.quantile (default 0.95) and gradient.quantile_bandwidth_ms
    (default 1), checked as the file's keys are. sens_margin sets gradient.sens_noise_margin (the
    sensitivities' accuracy, docs/optimize.md 12.4: 3e2 by default; smaller
    is more accurate at more steps, and acts only when solver.rtol is below
    margin x 7.4e-11; checked as the file's key is). sens_error_test ("on" or "off") sets
    gradient.sens_error_test: whether the sensitivities enter the integrator's error test
    (docs/optimize.md 12.5: off is as accurate at a tight solver.rtol for far fewer steps,
    less accurate at a loose one). Overrides may set only montecarlo.* keys and
    gradient.* keys: the models are built from the file's text (move a
    design key in the file or pass it in params)."""
    import json

    for key, value in (("gradient.sens_noise_margin", sens_margin),
                       ("gradient.sens_error_test", sens_error_test),
                       ("gradient.quantile", quantile),
                       ("gradient.quantile_bandwidth_ms", bandwidth_ms)):
        if value is not None:
            overrides = dict(overrides or {})
            overrides[key] = value
    cfg = _as_config(cfg, overrides)
    for key in cfg.overrides:
        if not key.startswith("montecarlo.") and not key.startswith("gradient."):
            _refuse("gradient: override %r: only montecarlo.* and gradient.* keys reach the "
                    "gradient; set it in the file" % key)
    keys = [_no_nul("params", str(k)) for k in params]
    if not keys or len(keys) > 16:
        _refuse("gradient: give 1 to 16 keys in params")
    n = 0 if maneuvers is None else int(maneuvers)
    if n < 0:
        _refuse("gradient: maneuvers must be >= 0")
    arr = (ctypes.c_char_p * len(keys))(*[k.encode() for k in keys])
    err = _Error()
    report = ctypes.c_void_p()
    with _Loaded(cfg) as L:
        st = _lib.pom_api_gradient_json(L.ptr, arr, len(keys), n, ctypes.byref(report), err)
    try:
        _check(st, err)
        return json.loads(ctypes.string_at(report.value).decode())
    finally:
        if report.value:
            _lib.pom_api_free(report)
