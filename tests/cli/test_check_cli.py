"""``lagrangian check``: the thin shell over ``System.check`` (text, JSON, exit 2)."""

from __future__ import annotations

import json

import pytest

from lagrangian.cli import ExitStatus, main


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_text_names_each_answer_and_its_verdict(capsys):
    status, out, err = run(
        capsys, "check", "simple_pendulum", "--kinetic", "m*l^2*theta_dot^2",
        "--potential", "m*g*l*(1 - cos(theta))", "--equation", "l*theta_ddot = g*sin(theta)",
        "--momentum", "p_theta=m*l^2*theta_dot",
    )  # fmt: skip
    assert (status, err) == (ExitStatus.SUCCESS, "")
    assert out.splitlines() == [
        "kinetic m*l^2*theta_dot^2: wrong",
        "  the term l^2*m*theta_dot^2 should be l^2*m*theta_dot^2/2",
        "potential m*g*l*(1 - cos(theta)): right",
        "equation l*theta_ddot = g*sin(theta): wrong",
        "  the equation of theta with errors (all terms on the left): the term -g*sin(theta) "
        "has the wrong sign: it should be g*sin(theta)",
        "momentum m*l^2*theta_dot: right",
    ]


def test_json_contract(capsys):
    status, out, _ = run(
        capsys, "check", "simple_pendulum", "--json",
        "--lagrangian", r"\frac{1}{2} m l^2 \dot{\theta}^2 - m g l \cos\theta",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    document = json.loads(out)
    assert document["verdict"] == "wrong"
    assert document["reason"] == (
        "the term -g*l*m*cos(theta) has the wrong sign: it should be g*l*m*cos(theta)"
    )
    assert document["terms"] == [
        {"term": "-g*l*m*cos(theta)", "problem": "sign", "expected": "g*l*m*cos(theta)"}
    ]


def test_equivalent_lagrangian_in_json(capsys):
    status, out, _ = run(
        capsys, "check", "simple_pendulum", "--json",
        "--lagrangian", "m*l^2*theta_dot^2/2 + m*g*l*cos(theta) + 3*theta_dot*sin(theta)",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    document = json.loads(out)
    assert (document["verdict"], document["terms"]) == ("equivalent", [])
    assert document["reason"] == (
        "right up to a total time derivative: the same equations of motion"
    )


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--kinetic", "m*l^2*thta_dot^2"],
         "--kinetic: unknown symbol 'thta_dot' (did you mean 'theta_dot'?) at position 7 in "
         "'m*l^2*thta_dot^2'"),
        (["--equation", "l*theta_ddot = (g"],
         "--equation 1: expected ')' to close '(' at position 16, found end of expression at "
         "position 18 in 'l*theta_ddot = (g'"),
        (["--potential", r"\frac{1}{2} m \dot{\phi}^2"],
         "--potential: unknown symbol 'phi_dot' at position 15 in "
         "'\\frac{1}{2} m \\dot{\\phi}^2'"),
        (["--momentum", "p_x=m*x_dot"],
         "--momentum: 'p_x' is not a momentum of the model (momenta: p_theta)"),
        ([], "give an answer to check: --kinetic, --potential, --lagrangian, --equation, "
             "--hamiltonian, --conserved or --momentum"),
    ],
)  # fmt: skip
def test_bad_input_is_one_line_and_exit_2(capsys, argv, message):
    status, out, err = run(capsys, "check", "simple_pendulum", *argv)
    assert status == ExitStatus.BAD_INPUT
    assert out == ""
    assert err == f"lagrangian: error: {message}\n"
