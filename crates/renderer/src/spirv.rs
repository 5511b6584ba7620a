//! Test support: the push-constant block of a compiled shader, its layout read from the
//! SPIR-V (member offsets and size; the optimiser strips names) and its names from the
//! GLSL, so that each Rust push struct can be checked against the block its shader
//! declares.

use std::collections::HashMap;

/// A shader's push-constant block as its SPIR-V lays it out.
#[derive(Debug, PartialEq, Eq)]
pub(crate) struct PushLayout {
    /// Bytes from the block's start to the end of its last member.
    pub size: u32,
    /// Each member's offset, in declaration order.
    pub offsets: Vec<u32>,
}

const OP_TYPE_INT: u32 = 21;
const OP_TYPE_FLOAT: u32 = 22;
const OP_TYPE_VECTOR: u32 = 23;
const OP_TYPE_ARRAY: u32 = 28;
const OP_TYPE_STRUCT: u32 = 30;
const OP_TYPE_POINTER: u32 = 32;
const OP_CONSTANT: u32 = 43;
const OP_VARIABLE: u32 = 59;
const OP_DECORATE: u32 = 71;
const OP_MEMBER_DECORATE: u32 = 72;
const DECORATION_ARRAY_STRIDE: u32 = 6;
const DECORATION_OFFSET: u32 = 35;
const STORAGE_CLASS_PUSH_CONSTANT: u32 = 9;

/// The type declarations of a module, as much of them as push blocks need.
#[derive(Default)]
struct Module {
    offsets: HashMap<(u32, u32), u32>,
    array_strides: HashMap<u32, u32>,
    types: HashMap<u32, Vec<u32>>,
    constants: HashMap<u32, u32>,
    pointers: HashMap<u32, (u32, u32)>,
    push_variable_type: Option<u32>,
}

impl Module {
    fn parse(spirv: &[u32]) -> Self {
        assert_eq!(spirv.first(), Some(&0x0723_0203), "not SPIR-V");
        let mut module = Self::default();
        let mut at = 5;
        while at < spirv.len() {
            let count = (spirv[at] >> 16) as usize;
            let opcode = spirv[at] & 0xffff;
            assert!(count > 0, "malformed SPIR-V");
            let operands = &spirv[at + 1..at + count];
            match opcode {
                OP_MEMBER_DECORATE if operands[2] == DECORATION_OFFSET => {
                    module
                        .offsets
                        .insert((operands[0], operands[1]), operands[3]);
                }
                OP_DECORATE if operands[1] == DECORATION_ARRAY_STRIDE => {
                    module.array_strides.insert(operands[0], operands[2]);
                }
                OP_TYPE_INT | OP_TYPE_FLOAT | OP_TYPE_VECTOR | OP_TYPE_ARRAY | OP_TYPE_STRUCT => {
                    let mut declaration = vec![opcode];
                    declaration.extend_from_slice(&operands[1..]);
                    module.types.insert(operands[0], declaration);
                }
                OP_TYPE_POINTER => {
                    module
                        .pointers
                        .insert(operands[0], (operands[1], operands[2]));
                }
                OP_CONSTANT => {
                    module.constants.insert(operands[1], operands[2]);
                }
                OP_VARIABLE if operands[2] == STORAGE_CLASS_PUSH_CONSTANT => {
                    let (_, pointee) = module.pointers[&operands[0]];
                    module.push_variable_type = Some(pointee);
                }
                _ => {}
            }
            at += count;
        }
        module
    }

    /// The size in bytes of type `id` as laid out in the module (explicit offsets and
    /// strides; scalars and vectors tightly packed).
    fn size(&self, id: u32) -> u32 {
        let declaration = &self.types[&id];
        match declaration[0] {
            OP_TYPE_INT | OP_TYPE_FLOAT => declaration[1] / 8,
            OP_TYPE_VECTOR => self.size(declaration[1]) * declaration[2],
            OP_TYPE_ARRAY => self.array_strides[&id] * self.constants[&declaration[2]],
            OP_TYPE_STRUCT => (1..declaration.len())
                .map(|member| {
                    self.offsets[&(id, member as u32 - 1)] + self.size(declaration[member])
                })
                .max()
                .unwrap_or(0),
            other => panic!("type opcode {other} not expected in a push block"),
        }
    }
}

/// The layout of the push-constant block `spirv` declares, if any.
pub(crate) fn push_layout(spirv: &[u32]) -> Option<PushLayout> {
    let module = Module::parse(spirv);
    let block = module.push_variable_type?;
    let members = module.types[&block].len() as u32 - 1;
    Some(PushLayout {
        size: module.size(block),
        offsets: (0..members).map(|m| module.offsets[&(block, m)]).collect(),
    })
}

/// The type name and member names of the push-constant block declared in `glsl`
/// (`layout(push_constant) uniform Name { type member; ... } push;`), if any.
pub(crate) fn glsl_push_members(glsl: &str) -> Option<(String, Vec<String>)> {
    let after = glsl.split("layout(push_constant) uniform ").nth(1)?;
    let (name, rest) = after.split_once('{')?;
    let (body, _) = rest.split_once('}')?;
    let members = body
        .lines()
        .map(|line| line.split("//").next().unwrap_or_default().trim())
        .filter(|line| !line.is_empty())
        .map(|line| {
            let declaration = line.strip_suffix(';').expect("one member per line");
            let name = declaration.split_whitespace().last().expect("a name");
            name.split('[').next().unwrap_or(name).to_owned()
        })
        .collect();
    Some((name.trim().to_owned(), members))
}
