"""A two-talker room made outside the project's simulator, for the microphone-pair chain.

Speech is synthesized by espeak-ng (read sentences, two voices, pauses between sentences, the
talkers overlapping); each pair's audio is rendered by pyroomacoustics' image-source model
(Scheibler, Bezzam & Dokmanić 2018) with the wanted T60 (inverse Sabine) and white noise at the
wanted SNR. Four pairs, one in the middle of each wall, 5 cm from it, 0.5 m baseline, as in
Pham's thesis (ch. 5.6.2). Talkers stand still, or with --moving circle 0.3 m around their spot
(rendered in 256 ms blocks).

Writes to OUT: one stereo 16 kHz WAV and one SensorDescriptor (JSON) per pair, the truth as
replay lines (`truth.jsonl`, 25 Hz), `scene.json` (the talkers' spurts, the room) and
`server.toml`, the fusion server's configuration a user would write for this room.

    python3 make_scene.py OUT --seed 1 [--moving] [--room 3,3,2.5] [--mic-height 1.2] [--inset 0.05]
"""

import argparse
import io
import json
import os
import subprocess
import wave
from math import gcd

import numpy as np
import pyroomacoustics as pra
from scipy.signal import resample_poly

RATE = 16_000
START = 1_763_700_000.0
BLOCK_S = 0.256
SENTENCES = [
    "The quick brown fox jumps over the lazy dog near the river bank.",
    "Please call Stella and ask her to bring these things with her from the store.",
    "We also need a small plastic snake and a big toy frog for the kids.",
    "She can scoop these things into three red bags, and we will go meet her on Wednesday.",
    "The meeting has been moved to the second floor conference room at noon.",
    "I think the weather will be better tomorrow, so we can walk to the park.",
    "Could you tell me where the nearest train station is, please?",
    "Our team finished the project two weeks ahead of the schedule.",
    "He read the newspaper every morning before going to work.",
    "There is a long line of people waiting outside the cinema tonight.",
]


def arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--moving", action="store_true", help="talkers circle 0.3 m around their spot")
    parser.add_argument("--room", default="3,3,2.5", help="x,y,z size in metres")
    parser.add_argument("--mic-height", type=float, default=1.2)
    parser.add_argument("--inset", type=float, default=0.05, help="metres from each pair to its wall")
    parser.add_argument("--t60", type=float, default=0.3)
    parser.add_argument("--snr", type=float, default=20.0, help="dB, over the samples with speech")
    parser.add_argument("--duration", type=float, default=40.0, help="seconds")
    return parser.parse_args()


def synthesize(text, voice, words_per_minute):
    """espeak-ng's rendering of `text`, resampled to RATE."""
    wav = subprocess.run(
        ["espeak-ng", "-v", voice, "-s", str(words_per_minute), "--stdout", text],
        capture_output=True,
        check=True,
    ).stdout
    with wave.open(io.BytesIO(wav)) as w:
        rate = w.getframerate()
        samples = np.frombuffer(w.readframes(w.getnframes()), dtype=np.int16) / 32768.0
    g = gcd(rate, RATE)
    return resample_poly(samples, RATE // g, rate // g)


def spurts_of(signal, offset_s):
    """Talk spurts of one sentence: 20 ms power above -40 dB of its peak, gaps under 150 ms closed."""
    power = np.convolve(signal**2, np.ones(320) / 320, mode="same")
    active = np.concatenate([[False], power > 1e-4 * power.max(), [False]])
    edges = np.flatnonzero(np.diff(active.astype(int)))
    spurts = []
    for start, end in zip(edges[::2], edges[1::2]):
        if spurts and start - spurts[-1][1] < 0.15 * RATE:
            spurts[-1][1] = end
        else:
            spurts.append([start, end])
    return [[offset_s + a / RATE, offset_s + b / RATE] for a, b in spurts if b - a > 0.05 * RATE]


def talker_track(rng, voice, first_s, duration):
    """A talker's dry signal (sentences with 0.5-3 s pauses from `first_s` on) and its spurts."""
    signal = np.zeros(int(duration * RATE))
    spurts = []
    t = first_s
    while t < duration - 1.0:
        text = SENTENCES[rng.integers(len(SENTENCES))]
        sentence = synthesize(text, voice, int(rng.integers(140, 175)))
        start = int(t * RATE)
        n = min(len(sentence), len(signal) - start)
        signal[start : start + n] += sentence[:n]
        spurts += spurts_of(sentence[:n], t)
        t += n / RATE + rng.uniform(0.5, 3.0)
    return signal / np.sqrt(np.mean(signal[signal != 0] ** 2)), spurts


def pairs_on_walls(room, height, inset):
    """One 0.5 m pair in the middle of each wall, `inset` metres from it."""
    cx, cy = room[0] / 2, room[1] / 2
    return {
        "mics_s": [[cx - 0.25, inset, height], [cx + 0.25, inset, height]],
        "mics_e": [[room[0] - inset, cy - 0.25, height], [room[0] - inset, cy + 0.25, height]],
        "mics_n": [[cx + 0.25, room[1] - inset, height], [cx - 0.25, room[1] - inset, height]],
        "mics_w": [[inset, cy + 0.25, height], [inset, cy - 0.25, height]],
    }


def render_pair(args, room, mics, dry, positions_at, rng):
    """One pair's reverberant, noisy stereo signal."""
    absorption, max_order = pra.inverse_sabine(args.t60, room)
    total = int(args.duration * RATE)
    out = np.zeros((2, total + RATE))
    block = int(BLOCK_S * RATE) if args.moving else total
    for talker, signal in enumerate(dry):
        for start in range(0, total, block):
            piece = signal[start : start + block]
            if not np.any(piece):
                continue
            shoebox = pra.ShoeBox(room, fs=RATE, materials=pra.Material(absorption), max_order=max_order)
            shoebox.add_source(positions_at(start / RATE)[talker])
            shoebox.add_microphone_array(np.array(mics).T)
            shoebox.compute_rir()
            for mic in range(2):
                wet = np.convolve(piece, shoebox.rir[mic][0])[: out.shape[1] - start]
                out[mic, start : start + len(wet)] += wet
    out = out[:, :total]
    speech_power = np.mean(out[:, np.abs(out[0]) > 1e-6] ** 2)
    out += rng.normal(0.0, np.sqrt(speech_power / 10 ** (args.snr / 10)), out.shape)
    return out / np.abs(out).max() * 0.9


def write_wav(path, stereo):
    with wave.open(path, "wb") as w:
        w.setnchannels(2)
        w.setsampwidth(2)
        w.setframerate(RATE)
        w.writeframes((stereo.T * 32767).astype(np.int16).tobytes())


def server_config(room):
    """What a user would write for talkers in this room (README: the talker configuration)."""
    return (
        "[site]\nname = \"speech_scene\"\nvolume_min = [0.0, 0.0, 0.0]\n"
        f"volume_max = [{room[0]}, {room[1]}, {room[2]}]\n\n"
        "[filter]\nspeech_activity = true\nmotion = \"random_walk\"\nposition_noise_std = 0.1\nbirth_rate = 0.05\n"
    )


def main():
    args = arguments()
    os.makedirs(args.out, exist_ok=True)
    rng = np.random.default_rng(args.seed)
    room = [float(v) for v in args.room.split(",")]
    voices = ["en+f3", "en+m3"] if args.seed % 2 else ["en-us+f2", "en+m1"]
    tracks = [talker_track(rng, v, 0.5 + 1.5 * k + rng.uniform(0, 1), args.duration) for k, v in enumerate(voices)]
    dry = [signal for signal, _ in tracks]
    spurts = [s for _, s in tracks]

    def spot():
        return [rng.uniform(0.6, room[0] - 0.6), rng.uniform(0.6, room[1] - 0.6), rng.uniform(1.5, 1.6)]

    spots = [spot(), spot()]
    while np.hypot(spots[0][0] - spots[1][0], spots[0][1] - spots[1][1]) <= 1.0:
        spots = [spot(), spot()]

    def positions_at(t):
        if not args.moving:
            return spots
        return [
            [p[0] + 0.3 * np.sin(2 * np.pi * t / (20 + 7 * k)), p[1] + 0.3 * np.cos(2 * np.pi * t / (20 + 7 * k)), p[2]]
            for k, p in enumerate(spots)
        ]

    for name, mics in pairs_on_walls(room, args.mic_height, args.inset).items():
        write_wav(f"{args.out}/{name}.wav", render_pair(args, room, mics, dry, positions_at, rng))
        model = {"kind": "mic_pair", "mics": mics, "speed_of_sound": 343.0, "noise_std": 6.25e-5}
        descriptor = {"version": 1, "site": "speech_scene", "sensor": name, "model": model,
                      "detection_probability": 0.7, "clutter_rate": 1.0}
        with open(f"{args.out}/{name}.json", "w") as f:
            json.dump(descriptor, f)
    with open(f"{args.out}/truth.jsonl", "w") as f:
        for i in range(int(args.duration * 25)):
            objects = [{"id": k + 1, "position": list(p)} for k, p in enumerate(positions_at(i / 25))]
            f.write(json.dumps({"truth": {"version": 1, "stamp": START + i / 25, "objects": objects}}) + "\n")
    with open(f"{args.out}/scene.json", "w") as f:
        json.dump({"spurts": spurts, "room": room, "start": START, "spots": spots}, f)
    with open(f"{args.out}/server.toml", "w") as f:
        f.write(server_config(room))
    shares = [sum(b - a for a, b in s) / args.duration for s in spurts]
    print(f"{args.out}: talkers at {np.round(spots, 2).tolist()}, talking {np.round(shares, 2).tolist()} of the time")


if __name__ == "__main__":
    main()
