"""Controller abstraction (the paper's Section 4.2): the FFT of each actuator's controller with
the below-threshold amplitudes suppressed.

An :class:`AbstractController` is a truncated Fourier series per actuator over one period T
(the learned controller's interval): ``u_i(t) = mean_i + sum_k a_ik cos(2 pi f_k t) -
b_ik sin(2 pi f_k t)``, kept only for the harmonics k whose amplitude is at least ``threshold``
times the largest harmonic amplitude in the controller. It is compact (a handful of numbers
per actuator), serialisable (:meth:`to_dict`), and playable at any duration (periodic
continuation of the learned window).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .tent import TentController, play


@dataclass(frozen=True)
class AbstractController:
    """Per actuator: ``mean`` (N,) and the kept harmonics ``harmonics`` (list of (K_i,) int
    arrays) with complex coefficients ``coefficients`` (list of (K_i,) complex arrays), over
    ``period`` s. Coefficients follow ``numpy.fft.rfft`` normalised so that a harmonic of
    amplitude A has |c| = A / 2. ``nyquist``: the harmonic at the Nyquist rate of the grid the
    controller was abstracted on (an even number of samples), or None; where kept, it is a
    cosine (its coefficient is real: one parameter, not two)."""

    mean: np.ndarray
    harmonics: tuple[np.ndarray, ...]
    coefficients: tuple[np.ndarray, ...]
    period: float
    nyquist: int | None = None

    @property
    def num_actuators(self) -> int:
        return len(self.mean)

    @property
    def num_coefficients(self) -> int:
        """Kept harmonics over all actuators."""
        return int(sum(len(h) for h in self.harmonics))

    def _complex(self, harmonics: np.ndarray) -> np.ndarray:
        """Which of an actuator's kept harmonics have an imaginary part (all but Nyquist)."""
        return harmonics != self.nyquist if self.nyquist is not None else np.ones(
            len(harmonics), dtype=bool)

    @property
    def num_parameters(self) -> int:
        """Real numbers that define the controller: means + 2 per kept harmonic (1 for the
        Nyquist harmonic, a cosine)."""
        return self.num_actuators + sum(len(h) + int(self._complex(h).sum())
                                        for h in self.harmonics)

    def __call__(self, t: np.ndarray | float) -> np.ndarray:
        """u(t), shape t.shape + (N,), clipped to [0, 1]; periodic with ``period``."""
        t = np.asarray(t, dtype=float)
        out = np.empty(t.shape + (self.num_actuators,))
        for i in range(self.num_actuators):
            phase = 2.0 * np.pi * np.multiply.outer(t, self.harmonics[i]) / self.period
            c = self.coefficients[i]
            series = 2.0 * (np.cos(phase) @ c.real - np.sin(phase) @ c.imag) if len(c) else 0.0
            out[..., i] = self.mean[i] + series
        return np.clip(out, 0.0, 1.0)

    def actions(self, dt: float, steps: int, t0: float = 0.0) -> np.ndarray:
        """(steps, N) float32 env actions a_k = 2 u(t0 + (k + 1) dt) - 1, any number of steps."""
        return play(self, dt, steps, t0)

    def frequency_parameters(self) -> np.ndarray:
        """The controller's real parameters as one vector in [0, 1]^(N + 2K), the space the
        optimisers search when they refine an abstraction (the paper's "frequency
        parameters"): the N means, then per actuator the real parts and then the imaginary
        parts of its kept coefficients (none for the Nyquist harmonic), each shifted by +0.5
        (|Re c|, |Im c| <= 0.5 bounds a harmonic's amplitude by sqrt(2); a signal in [0, 1]
        has |c| <= 1 / pi); clipped to the box."""
        parts = [self.mean]
        for h, c in zip(self.harmonics, self.coefficients):
            parts += [c.real + 0.5, c.imag[self._complex(h)] + 0.5]
        return np.clip(np.concatenate(parts), 0.0, 1.0)

    def with_frequency_parameters(self, vector: np.ndarray) -> AbstractController:
        """The controller with the same kept harmonics and the parameters ``vector``
        (the layout of :meth:`frequency_parameters`)."""
        vector = np.asarray(vector, dtype=float)
        if vector.shape != (self.num_parameters,):
            raise ValueError(f"expected {self.num_parameters} frequency parameters, got shape "
                             f"{vector.shape}")
        coefficients, k = [], self.num_actuators
        for h in self.harmonics:
            n, has_imag = len(h), self._complex(h)
            imag = np.zeros(n)
            imag[has_imag] = vector[k + n:k + n + int(has_imag.sum())] - 0.5
            coefficients.append((vector[k:k + n] - 0.5) + 1j * imag)
            k += n + int(has_imag.sum())
        return AbstractController(vector[:self.num_actuators].copy(), self.harmonics,
                                  tuple(coefficients), self.period, self.nyquist)

    def to_dict(self) -> dict:
        """JSON-ready description (lists of floats and ints)."""
        return {
            "period": float(self.period),
            "mean": [float(m) for m in self.mean],
            "harmonics": [[int(k) for k in h] for h in self.harmonics],
            "coefficients": [[[float(z.real), float(z.imag)] for z in c]
                             for c in self.coefficients],
            "nyquist": self.nyquist,
        }

    @classmethod
    def from_dict(cls, data: dict) -> AbstractController:
        return cls(
            mean=np.asarray(data["mean"], dtype=float),
            harmonics=tuple(np.asarray(h, dtype=int) for h in data["harmonics"]),
            coefficients=tuple(np.array([complex(re, im) for re, im in c], dtype=complex)
                               for c in data["coefficients"]),
            period=float(data["period"]),
            nyquist=data.get("nyquist"),
        )


def abstract(controller: TentController, threshold: float = 0.1,
             samples: int | None = None, max_parameters: int | None = None,
             mirror: bool = False) -> AbstractController:
    """FFT abstraction of a tent controller over its interval.

    The controller is sampled at ``samples`` evenly spaced times over one period, at the end of
    each of its ``samples`` steps (default: its node count less one, i.e. the nodal values
    themselves, the first node taken as the period's end: the same for a periodic controller);
    harmonics with amplitude below ``threshold`` times the largest harmonic amplitude of any
    actuator are suppressed (one threshold for the whole controller: an actuator that barely
    moves keeps only its mean). With ``max_parameters``, of those only the largest harmonics
    whose parameters, with the N means, fit in it are kept (a budget of real numbers; at least
    N, the means alone). ``mirror``, for a controller that is not periodic (a turn): the series
    of its window followed by the window played backwards (period twice the window), which
    has no jump where the window's end meets its start, so that a few harmonics hold it (a
    cosine series); it plays the controller over the window, then back.
    """
    if not 0.0 <= threshold < 1.0:
        raise ValueError(f"threshold must be in [0, 1), got {threshold!r}")
    count = samples or controller.num_nodes - 1
    values, period = _samples(controller, count, mirror)
    spectrum = np.fft.rfft(values, axis=0) / len(values)  # (len // 2 + 1, N)
    nyquist = len(values) // 2 if len(values) % 2 == 0 else None
    if nyquist is not None:  # the Nyquist term appears once in the series, not twice
        spectrum[-1] = 0.5 * spectrum[-1].real
    amplitudes = np.abs(spectrum[1:])  # (len // 2, N): harmonic k + 1 of each actuator
    largest = amplitudes.max() if len(amplitudes) else 0.0
    keep = (amplitudes >= threshold * largest) & (amplitudes > 1e-12)
    if max_parameters is not None:
        keep &= _largest_within(amplitudes, keep, max_parameters - controller.num_actuators,
                                nyquist)
    harmonics = tuple(np.flatnonzero(keep[:, i]) + 1 for i in range(controller.num_actuators))
    coefficients = tuple(spectrum[h, i].copy() for i, h in enumerate(harmonics))
    return AbstractController(mean=spectrum[0].real.copy(), harmonics=harmonics,
                              coefficients=coefficients, period=period, nyquist=nyquist)


def _samples(controller: TentController, count: int, mirror: bool
             ) -> tuple[np.ndarray, float]:
    """The values (M, N) the series is fitted to, one per phase step of its period, and that
    period, s: at the ends of the ``count`` steps of the window, the last (its end: phase 0)
    first, where a player reads a controller (u(t0 + (k + 1) dt)), a periodic controller's end
    being its start; mirrored, the window's count + 1 values from its start to its end and
    back (2 count, period twice the window)."""
    steps = np.arange(count + 1) / count
    if mirror:
        forward = controller(controller.t0 + controller.duration * steps)
        return np.concatenate([forward, forward[-2:0:-1]]), 2.0 * controller.duration
    values = controller(controller.t0 + controller.duration * steps[1:])
    return np.roll(values, 1, axis=0), controller.duration


def _largest_within(amplitudes: np.ndarray, allowed: np.ndarray, budget: int,
                    nyquist: int | None) -> np.ndarray:
    """(K, N) bool: the ``allowed`` harmonics, largest amplitude first, while their
    parameters (2 each, 1 for the Nyquist harmonic) fit in ``budget``."""
    chosen = np.zeros_like(allowed)
    for flat in np.argsort(-amplitudes, axis=None, kind="stable"):
        k, i = np.unravel_index(flat, amplitudes.shape)
        cost = 1 if nyquist is not None and k + 1 == nyquist else 2
        if allowed[k, i] and cost <= budget:
            chosen[k, i], budget = True, budget - cost
    return chosen


DEFAULT_THRESHOLDS = (0.5, 0.4, 0.3, 0.2, 0.15, 0.1, 0.05, 0.0)


def most_compact(controller: TentController, score, tolerance: float = 0.1,
                 thresholds: tuple[float, ...] = DEFAULT_THRESHOLDS, samples: int | None = None,
                 mirror: bool = False) -> tuple[AbstractController, list[dict]]:
    """The most compact abstraction whose objective is within ``tolerance`` of the learned
    controller's: E_abstract <= E_learned + tolerance * |E_learned|.

    ``score(list of controllers) -> (K,) E`` evaluates by simulation (the learned one first).
    Returns the chosen abstraction and a report row per threshold tried (threshold, kept
    coefficients, parameters, E), highest threshold first. ``samples``, ``mirror``: as
    :func:`abstract`'s.
    """
    candidates = [abstract(controller, th, samples, mirror=mirror) for th in thresholds]
    energies = np.asarray(score([controller, *candidates]), dtype=float)
    learned, rows = energies[0], []
    chosen = candidates[-1]
    for th, candidate, energy in zip(thresholds, candidates, energies[1:]):
        rows.append({"threshold": th, "coefficients": candidate.num_coefficients,
                     "parameters": candidate.num_parameters, "E": float(energy)})
    for candidate, energy in zip(candidates, energies[1:]):
        if energy <= learned + tolerance * abs(learned):
            chosen = candidate
            break
    return chosen, rows
