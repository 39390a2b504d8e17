"""Time-domain analysis: compiled Newmark / generalized-alpha stepping, Poincare sections,
spectra, Lyapunov exponents and motion classification. Generic: the system is
``M q'' + D(t) q' + K(t) q = f(t) + F_nl(q[nl], q'[nl])`` with a compiled force kernel."""

from rotorsfd.timedomain.classify import MotionClass, classify_motion, classify_result
from rotorsfd.timedomain.forcing import Forcing, HarmonicLoad, TimeVaryingMatrices
from rotorsfd.timedomain.integrate import integrate
from rotorsfd.timedomain.kernels import as_cfunc, cubic_spring_kernel, null_kernel
from rotorsfd.timedomain.lyapunov import LyapunovResult, largest_lyapunov
from rotorsfd.timedomain.poincare import (
    closed_curve_test,
    correlation_dimension,
    distinct_points,
    normalise,
    poincare_period,
)
from rotorsfd.timedomain.spectrum import (
    SpectralLine,
    SpectrumAnalysis,
    amplitude_spectrum,
    spectral_lines,
    two_frequency_fraction,
)
from rotorsfd.timedomain.step_records import TimeResult

__all__ = [
    "Forcing",
    "HarmonicLoad",
    "LyapunovResult",
    "MotionClass",
    "SpectralLine",
    "SpectrumAnalysis",
    "TimeResult",
    "TimeVaryingMatrices",
    "amplitude_spectrum",
    "as_cfunc",
    "classify_motion",
    "classify_result",
    "closed_curve_test",
    "correlation_dimension",
    "cubic_spring_kernel",
    "distinct_points",
    "integrate",
    "largest_lyapunov",
    "normalise",
    "null_kernel",
    "poincare_period",
    "spectral_lines",
    "two_frequency_fraction",
]
