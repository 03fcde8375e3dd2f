"""pvfc's MCAP logs read by independent readers: the ``mcap`` package (the format's reference
Python reader) and ``mcap-ros2-support`` (the ROS 2 CDR decoder Foxglove's own stack mirrors).
Every message decodes to the numbers pvfc wrote: the plot channels as float32, the energy
audit's columns as float64."""

import numpy as np
import pytest

import pvfc

mcap_reader = pytest.importorskip("mcap.reader")
mcap_ros2 = pytest.importorskip("mcap_ros2.decoder")


@pytest.fixture(scope="module")
def wall_log(tmp_path_factory):
    s = pvfc.Scenario.from_dict({**pvfc.Scenario.preset("contact_wall").to_dict(), "duration": 0.5})
    r = pvfc.simulate(s)
    path = tmp_path_factory.mktemp("logs") / "wall.mcap"
    r.write_mcap(path)
    return r, path


def test_the_reference_readers_decode_every_message(wall_log):
    r, path = wall_log
    ours = pvfc.read_mcap(path)
    with open(path, "rb") as f:
        reader = mcap_reader.make_reader(f, decoder_factories=[mcap_ros2.DecoderFactory()])
        summary = reader.get_summary()
        assert summary is not None and summary.chunk_indexes, "chunk indexes for seeking"
        assert {c.message_encoding for c in summary.channels.values()} == {"cdr"}
        assert {s.encoding for s in summary.schemas.values()} == {"ros2msg"}
        theirs = list(reader.iter_decoded_messages())
    assert len(theirs) == len(ours) == 3 * len(r)
    for (schema, channel, message, decoded), (topic, log_time, data) in zip(theirs, ours):
        assert channel.topic == topic and message.log_time == log_time
        assert schema.name.startswith("pvfc/msg/")
        for field, value in data.items():
            np.testing.assert_array_equal(np.asarray(getattr(decoded, field), dtype=float), value)


def test_audit_columns_are_float64_and_plot_columns_float32(wall_log):
    r, path = wall_log
    msgs = pvfc.read_mcap(path)
    ctl = [m[2] for m in msgs if m[0] == "/pvfc/controller"]
    contact = [m[2] for m in msgs if m[0] == "/pvfc/contact"]
    np.testing.assert_array_equal([m["energy"] for m in ctl], r.energy)
    np.testing.assert_array_equal([m["work_contact"] for m in contact], r.contact["work_contact"])
    np.testing.assert_array_equal(
        [m["normal_force"] for m in contact], r.contact["normal_force"].astype(np.float32)
    )
    # float32 is visible: the log's U is not the run's to the last bit everywhere.
    u = np.array([m["potential"] for m in ctl])
    assert np.any(u != r.potential) and np.allclose(u, r.potential, rtol=1e-6)


def test_a_log_at_a_rate_keeps_one_sample_per_period_and_the_last(wall_log, tmp_path):
    r, _ = wall_log
    path = tmp_path / "wall_100hz.mcap"
    r.write_mcap(path, rate=100.0)
    ctl = [(m[1], m[2]) for m in pvfc.read_mcap(path) if m[0] == "/pvfc/controller"]
    times = np.array([t for t, _ in ctl]) * 1e-9
    # 0.5 s at 100 Hz: 0, 0.01, ..., 0.5 (the last sample is on the grid too).
    np.testing.assert_allclose(times, np.arange(51) * 0.01, atol=1e-9)
    kept = np.searchsorted(r.t, times - 1e-12)
    np.testing.assert_array_equal([m["energy"] for _, m in ctl], r.energy[kept])
    for bad in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(pvfc.PvfcError, match="log rate"):
            r.write_mcap(tmp_path / "bad.mcap", rate=bad)
