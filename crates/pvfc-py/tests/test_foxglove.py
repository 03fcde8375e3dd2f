"""The 3-D channels of an arm's log, checked against the ``foxglove-sdk`` Python package: the
schemas are Foxglove's own (name, encoding and descriptor bytes), and every message is the one
the SDK encodes from the same values. The tool frame sits where pvfc's forward kinematics
(proven against Pinocchio) puts it."""

import numpy as np
import pytest

import pvfc

fg = pytest.importorskip("foxglove.messages")
mcap_reader = pytest.importorskip("mcap.reader")


@pytest.fixture(scope="module")
def ur5_log(repo, tmp_path_factory):
    s = pvfc.Scenario.from_file(repo / "scenarios" / "ur5_cartesian.toml")
    s = pvfc.Scenario.from_dict({**s.to_dict(), "duration": 1.0}, base_dir=repo / "scenarios")
    r = pvfc.simulate(s)
    path = tmp_path_factory.mktemp("logs") / "ur5.mcap"
    r.write_mcap(path, s)
    with open(path, "rb") as f:
        reader = mcap_reader.make_reader(f)
        raw = [(c.topic, sch, m) for sch, c, m in reader.iter_messages()]
    return s, r, raw, pvfc.read_mcap(path)


def stamp(d):
    return fg.Timestamp(d["sec"], d["nsec"])


def vec(cls, d):
    return cls(**d)


def transforms(d):
    return fg.FrameTransforms(
        transforms=[
            fg.FrameTransform(
                timestamp=stamp(t["timestamp"]),
                parent_frame_id=t["parent_frame_id"],
                child_frame_id=t["child_frame_id"],
                translation=vec(fg.Vector3, t["translation"]),
                rotation=vec(fg.Quaternion, t["rotation"]),
            )
            for t in d["transforms"]
        ]
    )


def scene_update(d):
    kinds = {"LINE_STRIP": fg.LinePrimitiveLineType.LineStrip, "LINE_LOOP": fg.LinePrimitiveLineType.LineLoop}
    return fg.SceneUpdate(
        entities=[
            fg.SceneEntity(
                timestamp=stamp(e["timestamp"]),
                frame_id=e["frame_id"],
                id=e["id"],
                lines=[
                    fg.LinePrimitive(
                        type=kinds[line["type"]],
                        thickness=line["thickness"],
                        points=[vec(fg.Point3, p) for p in line["points"]],
                        color=vec(fg.Color, line["color"]),
                    )
                    for line in e["lines"]
                ],
            )
            for e in d["entities"]
        ]
    )


def test_schemas_are_foxgloves_own(ur5_log):
    _, _, raw, _ = ur5_log
    seen = {}
    for topic, schema, _ in raw:
        seen[topic] = schema
    expected = {"/tf": fg.FrameTransforms, "/scene/arm": fg.SceneUpdate, "/scene/path": fg.SceneUpdate}
    for topic, cls in expected.items():
        ours, theirs = seen[topic], cls.get_schema()
        assert (ours.name, ours.encoding) == (theirs.name, theirs.encoding)
        assert bytes(ours.data) == bytes(theirs.data)


def test_messages_are_what_the_sdk_encodes(ur5_log):
    _, _, raw, decoded = ur5_log
    build = {"/tf": transforms, "/scene/arm": scene_update, "/scene/path": scene_update}
    counts = {t: 0 for t in build}
    # The readers may order messages of equal time differently: pair them by topic and time.
    by_key = {(topic, t): data for topic, t, data in decoded}
    assert len(by_key) == len(decoded) == len(raw)
    for topic, _, message in raw:
        if topic in build:
            data = by_key[(topic, message.log_time)]
            assert build[topic](data).encode() == bytes(message.data)
            counts[topic] += 1
    # 1 s at 1 kHz (1,001 samples, t = 0 and 1 included), frames at 50 Hz; the path once.
    assert counts == {"/tf": 51, "/scene/arm": 51, "/scene/path": 1}


def test_tool_frame_is_the_forward_kinematics(ur5_log, repo):
    s, r, _, decoded = ur5_log
    robot = pvfc.Robot.from_urdf(repo / "models" / "ur5" / "ur5_robot.urdf", tip="tool0")
    index = {int(round(t * 1e9)): i for i, t in enumerate(r.t)}
    frames = [(m[1], m[2]) for m in decoded if m[0] == "/tf"]
    assert frames
    for ns, d in frames:
        names = [t["child_frame_id"] for t in d["transforms"]]
        assert names[-1] == "tool" and len(names) == robot.dof + 1
        tool = d["transforms"][-1]["translation"]
        pose = robot.tool_pose(r.q[index[ns]])
        np.testing.assert_allclose([tool["x"], tool["y"], tool["z"]], pose[:3, 3], atol=1e-12)
    path = [m[2] for m in decoded if m[0] == "/scene/path"][0]
    lines = path["entities"][0]["lines"]
    assert len(lines) == 2  # the desired contour's tool path, and the Cartesian path
