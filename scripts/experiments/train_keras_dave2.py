#!/usr/bin/env python3
"""Trains a Keras DAVE-2 on a `wogan dataset` folder the way the Udacity course's solution does
(naokishibuya/car-behavioral-cloning `model.py` and `utils.py`), and saves it as a Keras `.h5`
that examples/onnx/keras_to_onnx.py converts. Dev-time (issue 63, "the loop closed"):

    target/keras-venv/bin/python scripts/experiments/train_keras_dave2.py DATA OUT.h5 [--epochs N]

Needs tensorflow-cpu 2.15 (Keras 2: the `.h5` it writes is the Keras 2 layout the converter
reads), numpy, opencv-python-headless and Pillow (target/keras-venv; the experiment's log says how
it was made). Deterministic for a seed as far as TensorFlow's CPU kernels are.

What is the course's, kept: the architecture (Lambda x / 127.5 - 1, five convolutions with ELU,
Dropout 0.5, Dense 100-50-10 with ELU, 1), the preprocessing (crop 60 / 25, resize to 200 x 66,
RGB to YUV: the `udacity` contract), a random choice among the centre, left (+0.2) and right
(-0.2) pictures, a random horizontal flip with the steering negated, a random horizontal shift
(0.002 per pixel), mean squared error, Adam at 1e-4, batches of 40. Left out: the course's random
shadows and brightness (wogan's world has neither) and its vertical shift. Validation: a fifth of
the rows, centre pictures only.
"""
import argparse
import csv
import os
import random

import cv2
import numpy as np

IMAGE_HEIGHT, IMAGE_WIDTH, IMAGE_CHANNELS = 66, 200, 3
SIDE_CORRECTION = 0.2
SHIFT_PER_PIXEL = 0.002
SHIFT_RANGE_PX = 100


def preprocess(image):
    """The `udacity` contract: crop, resize (bilinear, as the course's call ends up), RGB to YUV."""
    image = image[60:-25, :, :]
    image = cv2.resize(image, (IMAGE_WIDTH, IMAGE_HEIGHT), interpolation=cv2.INTER_LINEAR)
    return cv2.cvtColor(image, cv2.COLOR_RGB2YUV)


def load(data, path):
    return cv2.cvtColor(cv2.imread(os.path.join(data, path)), cv2.COLOR_BGR2RGB)


def augmented(data, row, rng):
    """One training example from a log row: a camera chosen at random, flipped and shifted."""
    centre, left, right, steering = row[0], row[1], row[2], float(row[3])
    choice = rng.randrange(3)
    if choice == 0:
        image, steering = load(data, left), steering + SIDE_CORRECTION
    elif choice == 1:
        image, steering = load(data, right), steering - SIDE_CORRECTION
    else:
        image = load(data, centre)
    if rng.random() < 0.5:
        image, steering = cv2.flip(image, 1), -steering
    shift = SHIFT_RANGE_PX * (rng.random() - 0.5)
    steering += shift * SHIFT_PER_PIXEL
    matrix = np.float32([[1, 0, shift], [0, 1, 0]])
    image = cv2.warpAffine(image, matrix, (image.shape[1], image.shape[0]), borderMode=cv2.BORDER_REPLICATE)
    return preprocess(image), steering


def batches(data, rows, batch_size, training, seed):
    rng = random.Random(seed)
    while True:
        order = list(rows)
        if training:
            rng.shuffle(order)
        for start in range(0, len(order) - batch_size + 1, batch_size):
            images, labels = [], []
            for row in order[start:start + batch_size]:
                if training:
                    image, steering = augmented(data, row, rng)
                else:
                    image, steering = preprocess(load(data, row[0])), float(row[3])
                images.append(image)
                labels.append(steering)
            yield np.asarray(images, dtype=np.float32), np.asarray(labels, dtype=np.float32)


def model():
    from tensorflow import keras
    from tensorflow.keras import layers

    return keras.Sequential([
        keras.Input(shape=(IMAGE_HEIGHT, IMAGE_WIDTH, IMAGE_CHANNELS)),
        layers.Lambda(lambda x: x / 127.5 - 1.0),
        layers.Conv2D(24, 5, strides=2, activation="elu"),
        layers.Conv2D(36, 5, strides=2, activation="elu"),
        layers.Conv2D(48, 5, strides=2, activation="elu"),
        layers.Conv2D(64, 3, activation="elu"),
        layers.Conv2D(64, 3, activation="elu"),
        layers.Dropout(0.5),
        layers.Flatten(),
        layers.Dense(100, activation="elu"),
        layers.Dense(50, activation="elu"),
        layers.Dense(10, activation="elu"),
        layers.Dense(1),
    ])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data", help="a `wogan dataset` folder")
    parser.add_argument("out", help="the trained model, Keras .h5")
    parser.add_argument("--epochs", type=int, default=10)
    parser.add_argument("--steps", type=int, default=500, help="batches per epoch")
    parser.add_argument("--batch-size", type=int, default=40)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    if os.path.exists(args.out):
        parser.error(f"{args.out} exists: a model is never written over")

    import tensorflow as tf
    tf.keras.utils.set_random_seed(args.seed)
    with open(os.path.join(args.data, "driving_log.csv")) as f:
        rows = list(csv.reader(f))
    random.Random(args.seed).shuffle(rows)
    cut = len(rows) // 5
    validation, training = rows[:cut], rows[cut:]
    print(f"{len(training)} training rows, {len(validation)} validation rows")
    net = model()
    net.compile(loss="mean_squared_error", optimizer=tf.keras.optimizers.Adam(learning_rate=1e-4))
    net.fit(batches(args.data, training, args.batch_size, True, args.seed),
            steps_per_epoch=args.steps, epochs=args.epochs,
            validation_data=batches(args.data, validation, args.batch_size, False, args.seed),
            validation_steps=max(len(validation) // args.batch_size, 1), verbose=2)
    net.save(args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
